#include "edsp/transport/decode.h"
#include "edsp/logger/channel_csv_export.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "edsp/logger/log_reader.h"
#include "edsp/message_types.h"

namespace edsp {

namespace {

// Column names and values of one message, in field order.
class CsvRow {
 public:
  void Add(const std::string& name, std::int64_t v) { Push(name, std::to_string(v)); }
  void Add(const std::string& name, std::int32_t v) { Add(name, static_cast<std::int64_t>(v)); }
  void Add(const std::string& name, std::int8_t v) { Add(name, static_cast<std::int64_t>(v)); }
  void Add(const std::string& name, double v) { Push(name, fmt::format("{:.17g}", v)); }
  void Add(const std::string& name, const std::string& v) { Push(name, Quote(v)); }
  template <typename T, std::size_t N>
  void Add(const std::string& name, const T (&v)[N]) {
    for (std::size_t i = 0; i < N; ++i) Add(name + "_" + std::to_string(i + 1), v[i]);
  }

  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& values() const { return values_; }

 private:
  void Push(const std::string& name, std::string value) {
    names_.push_back(name);
    values_.push_back(std::move(value));
  }
  // RFC 4180: quote always, double the quotes inside (config_toml spans lines).
  static std::string Quote(const std::string& v) {
    std::string out = "\"";
    for (char c : v) {
      if (c == '"') out += '"';
      out += c;
    }
    return out + "\"";
  }
  std::vector<std::string> names_, values_;
};

void Fields(const pose_setpoint_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("pose", m.pose), r->Add("velocity", m.velocity), r->Add("acceleration", m.acceleration);
  r->Add("trajectory", m.trajectory), r->Add("segment", m.segment);
}
void Fields(const leg_command_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("setpoint_utime", m.setpoint_utime), r->Add("setpoint_seq", m.setpoint_seq);
  r->Add("pr_mode", m.pr_mode), r->Add("ik_length_m", m.ik_length_m);
  r->Add("pr_correction_m", m.pr_correction_m), r->Add("command_length_m", m.command_length_m);
  r->Add("motor_angle_rad", m.motor_angle_rad);
}
void Fields(const leg_state_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("command_seq", m.command_seq);
  r->Add("motor_angle_rad", m.motor_angle_rad), r->Add("motor_velocity_rad_s", m.motor_velocity_rad_s);
  r->Add("encoder_length_m", m.encoder_length_m), r->Add("drive_status", m.drive_status);
}
void Fields(const platform_state_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("pose", m.pose);
  r->Add("target_pose", m.target_pose), r->Add("observation_point_m", m.observation_point_m);
  r->Add("fk_status", m.fk_status), r->Add("fk_residual_m", m.fk_residual_m);
}
void Fields(const platform_config_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("preset", m.preset);
  r->Add("base_joints_m", m.base_joints_m), r->Add("platform_joints_m", m.platform_joints_m);
  r->Add("base_axes", m.base_axes), r->Add("platform_axes", m.platform_axes);
  r->Add("home_height_m", m.home_height_m), r->Add("lead_m", m.lead_m);
  r->Add("pr_sign", m.pr_sign), r->Add("gear_ratio", m.gear_ratio);
  r->Add("leg_min_m", m.leg_min_m), r->Add("leg_max_m", m.leg_max_m);
  r->Add("joint_angle_max_rad", m.joint_angle_max_rad);
  r->Add("observation_point_m", m.observation_point_m), r->Add("config_toml", m.config_toml);
}
void Fields(const tracker_point_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("point_m", m.point_m);
  r->Add("sigma_m", m.sigma_m), r->Add("valid", m.valid);
}
void Fields(const rig_truth_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("pose", m.pose);
  r->Add("leg_length_m", m.leg_length_m), r->Add("twist_rad", m.twist_rad);
  r->Add("observation_point_m", m.observation_point_m);
}
void Fields(const node_status_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("node", m.node), r->Add("pid", m.pid);
  r->Add("state", m.state), r->Add("messages_in", m.messages_in);
  r->Add("messages_out", m.messages_out), r->Add("drops", m.drops);
  r->Add("rejected", m.rejected), r->Add("deadline_misses", m.deadline_misses);
  r->Add("loop_p50_us", m.loop_p50_us), r->Add("loop_p99_us", m.loop_p99_us);
  r->Add("loop_max_us", m.loop_max_us);
}
void Fields(const fault_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("node", m.node);
  r->Add("channel", m.channel), r->Add("severity", m.severity), r->Add("code", m.code);
  r->Add("reason", m.reason);
}
void Fields(const arm_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("operator_name", m.operator_name);
}
void Fields(const pr_mode_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("pr_mode", m.pr_mode), r->Add("operator_name", m.operator_name);
}
void Fields(const calibration_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("operator_name", m.operator_name), r->Add("origin", m.origin), r->Add("model_json", m.model_json);
  r->Add("apply_ambiguous", m.apply_ambiguous);
}

void Fields(const motion_request_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("client", m.client), r->Add("kind", m.kind);
  r->Add("relative", m.relative), r->Add("frame", m.frame), r->Add("pose", m.pose), r->Add("point", m.point);
  r->Add("speed_m_s", m.speed_m_s), r->Add("speed_rad_s", m.speed_rad_s);
  r->Add("accel_m_s2", m.accel_m_s2), r->Add("accel_rad_s2", m.accel_rad_s2);
  r->Add("motions", m.motions), r->Add("csv_text", m.csv_text), r->Add("csv_origin", m.csv_origin);
}

void Fields(const motion_reply_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("request_id", m.request_id), r->Add("kind", m.kind), r->Add("accepted", m.accepted);
  r->Add("reason", m.reason), r->Add("duration_s", m.duration_s), r->Add("start_delay_s", m.start_delay_s);
}

void Fields(const motion_status_t& m, CsvRow* r) {
  r->Add("utime", m.utime), r->Add("seq", m.seq), r->Add("session_id", m.session_id);
  r->Add("state", m.state), r->Add("request_id", m.request_id), r->Add("activity", m.activity);
  r->Add("progress", m.progress), r->Add("queued", m.queued), r->Add("last_end", m.last_end);
  r->Add("pose_commanded", m.pose_commanded), r->Add("pose_target", m.pose_target);
  r->Add("pose_measured", m.pose_measured), r->Add("measured_valid", m.measured_valid);
  r->Add("on_target", m.on_target), r->Add("frame", m.frame), r->Add("pivot", m.pivot), r->Add("reason", m.reason);
}

struct MessageType {
  std::int64_t fingerprint;
  std::string name;
  std::function<bool(const LogEvent&, CsvRow*)> to_row;
};

template <typename Msg>
MessageType Describe() {
  return {Msg::getHash(), std::string("edsp.") + Msg::getTypeName(), [](const LogEvent& e, CsvRow* row) {
            Msg msg;
            if (!DecodeUntrusted(&msg, e.data.data(), e.data.size())) return false;
            Fields(msg, row);
            return true;
          }};
}

// Every edsp message type (message_types.h): one without Fields() above does
// not compile.
const std::vector<MessageType>& KnownTypes() {
  static const std::vector<MessageType> types = [] {
    std::vector<MessageType> all;
    ForEachMessageType([&all](auto tag) { all.push_back(Describe<typename decltype(tag)::type>()); });
    return all;
  }();
  return types;
}

const MessageType* FindType(const LogEvent& event) {
  EdspHeader header;
  if (!ParseEdspHeader(event.data, &header)) return nullptr;
  for (const MessageType& t : KnownTypes()) {
    if (t.fingerprint == header.fingerprint) return &t;
  }
  return nullptr;
}

// A channel name made safe as a file name ('/' or spaces in foreign channels).
std::string FileNameFor(const std::string& channel) {
  std::string name = channel;
  for (char& c : name) {
    const bool safe = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    if (!safe) c = '_';
  }
  if (name.empty() || name[0] == '.') name = "_" + name;
  return name + ".csv";
}

struct OpenCsv {
  ChannelCsv info;
  const MessageType* type = nullptr;
  std::ofstream out;
};

void WriteLine(std::ofstream& out, double log_time_s, const std::vector<std::string>& cells) {
  out << fmt::format("{:.6f}", log_time_s);
  for (const std::string& cell : cells) out << ',' << cell;
  out << '\n';
}

}  // namespace

ChannelCsvExport ExportChannelCsvs(const std::string& log_path, const std::string& out_dir,
                                   const std::string& channel_regex) {
  std::regex filter;
  try {
    filter = std::regex(channel_regex);
  } catch (const std::regex_error& e) {
    throw std::runtime_error("--channels '" + channel_regex + "': not a regular expression (" +
                             e.what() + ")");
  }
  LogReader reader(log_path);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw std::runtime_error(out_dir + ": cannot create directory (" + ec.message() + ")");

  ChannelCsvExport result;
  std::map<std::string, std::unique_ptr<OpenCsv>> files;
  std::int64_t first_utime = -1;
  LogEvent event;
  while (reader.Next(&event)) {
    if (first_utime < 0) first_utime = event.timestamp_utime;
    if (!std::regex_match(event.channel, filter)) continue;
    auto& file = files[event.channel];
    const MessageType* type = FindType(event);
    CsvRow row;
    const bool decoded = type != nullptr && (!file || file->type == type) && type->to_row(event, &row);
    if (!decoded) {
      if (file) ++file->info.skipped;
      else ++result.unknown[event.channel];
      if (!file) files.erase(event.channel);
      continue;
    }
    if (!file) {
      file = std::make_unique<OpenCsv>();
      file->type = type;
      file->info.type = type->name;
      file->info.skipped = result.unknown[event.channel];  // what came before it
      result.unknown.erase(event.channel);
      file->info.path = (std::filesystem::path(out_dir) / FileNameFor(event.channel)).string();
      file->out.open(file->info.path);
      if (!file->out) throw std::runtime_error(file->info.path + ": cannot create file");
      file->out << "log_time_s";
      for (const std::string& name : row.names()) file->out << ',' << name;
      file->out << '\n';
    }
    WriteLine(file->out, static_cast<double>(event.timestamp_utime - first_utime) * 1e-6, row.values());
    ++file->info.rows;
  }
  for (auto& [channel, file] : files) {
    file->out.close();
    if (!file->out) throw std::runtime_error(file->info.path + ": write failed (disk full?)");
    result.channels[channel] = file->info;
  }
  result.damaged = reader.damaged();
  result.damage_offset = reader.damage_offset();
  return result;
}

}  // namespace edsp
