#include "edsp/transport/decode.h"
#include "edsp/logger/measurement_export.h"

#include <fmt/format.h>

#include "edsp/leg_command_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/logger/log_reader.h"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/tracker_point_t.hpp"

namespace edsp {

namespace {

template <typename Msg>
bool Decode(const LogEvent& event, Msg* msg) {
  return DecodeUntrusted(msg, event.data.data(), event.data.size());
}

void WriteHeader(std::ostream& out) {
  out << "time_s,run,pose_cmd_x_m,pose_cmd_y_m,pose_cmd_z_m,pose_cmd_roll_rad,pose_cmd_pitch_rad,"
         "pose_cmd_yaw_rad";
  for (int i = 1; i <= 6; ++i) out << ",leg_cmd_" << i << "_m";
  for (int i = 1; i <= 6; ++i) out << ",leg_enc_" << i << "_m";
  out << ",point_x_m,point_y_m,point_z_m\n";
}

}  // namespace

MeasurementExport ExportMeasurementCsv(const std::string& log_path, std::ostream& out) {
  LogReader reader(log_path);
  MeasurementExport result;
  pose_setpoint_t setpoint{};
  leg_command_t command{};
  leg_state_t legs{};
  bool have_setpoint = false, have_command = false, have_legs = false;
  std::int64_t first_utime = -1;
  WriteHeader(out);
  LogEvent event;
  while (reader.Next(&event)) {
    if (event.channel == "EDSP_SETPOINT") {
      have_setpoint = Decode(event, &setpoint) || have_setpoint;
    } else if (event.channel == "EDSP_LEG_COMMAND") {
      have_command = Decode(event, &command) || have_command;
    } else if (event.channel == "EDSP_LEG_STATE") {
      have_legs = Decode(event, &legs) || have_legs;
    } else if (event.channel == "EDSP_TRACKER") {
      tracker_point_t point{};
      if (!Decode(event, &point) || !point.valid || !have_setpoint || !have_command) {
        ++result.skipped;
        continue;
      }
      if (first_utime < 0) first_utime = point.utime;
      const std::string run = setpoint.trajectory.substr(0, setpoint.trajectory.find('/'));
      out << fmt::format("{:.6f},{}", static_cast<double>(point.utime - first_utime) * 1e-6, run);
      for (double v : setpoint.pose) out << fmt::format(",{:.17g}", v);
      for (double v : command.command_length_m) out << fmt::format(",{:.17g}", v);
      for (int i = 0; i < 6; ++i) {
        out << (have_legs ? fmt::format(",{:.17g}", legs.encoder_length_m[i]) : std::string(","));
      }
      out << fmt::format(",{:.17g},{:.17g},{:.17g}\n", point.point_m[0], point.point_m[1],
                         point.point_m[2]);
      ++result.rows;
    }
  }
  result.damaged = reader.damaged();
  result.damage_offset = reader.damage_offset();
  return result;
}

}  // namespace edsp
