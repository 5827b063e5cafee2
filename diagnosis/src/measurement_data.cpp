#include "edsp/diagnosis/measurement_data.h"

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/logger/measurement_export.h"

namespace edsp::gap {

namespace {

// Splits one CSV line into fields, remembering each field's 1-based column.
struct Field {
  std::string text;
  int column = 1;
};

std::vector<Field> SplitCsvLine(const std::string& line) {
  std::vector<Field> fields;
  Field current;
  int column = 1;
  for (std::size_t k = 0; k <= line.size(); ++k) {
    if (k == line.size() || line[k] == ',') {
      fields.push_back(current);
      current = Field{};
      column = static_cast<int>(k) + 2;
      current.column = column;
      continue;
    }
    if (line[k] != '\r' && line[k] != '"') current.text += line[k];
  }
  return fields;
}

std::string Trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t") - begin + 1);
}

// Column indices of the §3 columns in this file's header.
struct CsvColumns {
  int time = -1, run = -1;
  int pose[6] = {}, leg_cmd[6] = {}, leg_enc[6] = {-1, -1, -1, -1, -1, -1}, point[3] = {};
  bool has_encoder = false;
  int leg_corr[6] = {-1, -1, -1, -1, -1, -1};  // optional, all six or none
  int timing_event = -1;                       // optional
};

// leg_corr_1_m … leg_corr_6_m: all six or none (a correction of some legs
// only would be read as zero on the others, a wrong nominal residual).
void FindCorrectionColumns(const std::map<std::string, int>& index, const std::string& origin, int line,
                           CsvColumns* c) {
  int found = 0;
  for (int k = 0; k < 6; ++k) {
    const auto it = index.find(fmt::format("leg_corr_{}_m", k + 1));
    c->leg_corr[k] = it == index.end() ? -1 : it->second;
    found += it != index.end();
  }
  if (found == 0 || found == 6) return;
  for (int k = 0; k < 6; ++k) {
    if (c->leg_corr[k] < 0) {
      throw MeasurementError(fmt::format("{}:{}: header has {} of the six leg_corr columns but lacks \"leg_corr_{}_m\"",
                                         origin, line, found, k + 1));
    }
  }
}

CsvColumns FindColumns(const std::vector<Field>& header, const std::string& origin, int line) {
  std::map<std::string, int> index;
  for (std::size_t k = 0; k < header.size(); ++k) index[Trim(header[k].text)] = static_cast<int>(k);
  auto required = [&](const std::string& name) {
    const auto it = index.find(name);
    if (it == index.end()) {
      throw MeasurementError(fmt::format("{}:{}: header lacks the required column \"{}\"", origin, line, name));
    }
    return it->second;
  };
  CsvColumns c;
  c.time = required("time_s");
  c.run = required("run");
  const char* pose_names[6] = {"pose_cmd_x_m",      "pose_cmd_y_m",       "pose_cmd_z_m",
                               "pose_cmd_roll_rad", "pose_cmd_pitch_rad", "pose_cmd_yaw_rad"};
  for (int k = 0; k < 6; ++k) c.pose[k] = required(pose_names[k]);
  for (int k = 0; k < 6; ++k) c.leg_cmd[k] = required(fmt::format("leg_cmd_{}_m", k + 1));
  int encoders = 0;
  for (int k = 0; k < 6; ++k) {
    const auto it = index.find(fmt::format("leg_enc_{}_m", k + 1));
    c.leg_enc[k] = it == index.end() ? -1 : it->second;
    encoders += it != index.end();
  }
  c.has_encoder = encoders == 6;
  const char* point_names[3] = {"point_x_m", "point_y_m", "point_z_m"};
  for (int k = 0; k < 3; ++k) c.point[k] = required(point_names[k]);
  const auto timing = index.find("timing_event");
  c.timing_event = timing == index.end() ? -1 : timing->second;
  FindCorrectionColumns(index, origin, line, &c);
  return c;
}

class RowParser {
 public:
  RowParser(const std::string& origin, int line, const std::vector<Field>& fields)
      : origin_(origin), line_(line), fields_(fields) {}

  double Number(int index, const char* what) const {
    const Field& f = At(index, what);
    const std::string text = Trim(f.text);
    if (text.empty()) throw Error(f, fmt::format("{} is empty", what));
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size()) throw Error(f, fmt::format("{} \"{}\" is not a number", what, text));
    if (!std::isfinite(value)) throw Error(f, fmt::format("{} is {} (not finite)", what, text));
    return value;
  }

  // Empty is allowed for optional columns (a log without encoder data).
  bool OptionalNumber(int index, const char* what, double* value) const {
    if (index < 0 || Trim(At(index, what).text).empty()) return false;
    *value = Number(index, what);
    return true;
  }

  [[noreturn]] void Fail(int index, const char* what, const std::string& why) const {
    throw Error(At(index, what), why);
  }

  std::string Text(int index, const char* what) const {
    const std::string text = Trim(At(index, what).text);
    if (text.empty()) throw Error(At(index, what), fmt::format("{} is empty", what));
    return text;
  }

 private:
  const Field& At(int index, const char* what) const {
    if (index >= static_cast<int>(fields_.size())) {
      throw MeasurementError(
          fmt::format("{}:{}: row has {} fields, {} is missing", origin_, line_, fields_.size(), what));
    }
    return fields_[static_cast<std::size_t>(index)];
  }
  MeasurementError Error(const Field& f, const std::string& what) const {
    return MeasurementError(fmt::format("{}:{}:{}: {}", origin_, line_, f.column, what));
  }

  const std::string& origin_;
  int line_;
  const std::vector<Field>& fields_;
};

// `timing_event`: empty or 0 a sample like any other, 1 one to leave out.
bool FlaggedTimingEvent(const RowParser& p, int column) {
  double flag = 0.0;
  if (!p.OptionalNumber(column, "timing_event", &flag)) return false;
  if (flag != 0.0 && flag != 1.0)
    p.Fail(column, "timing_event", fmt::format("timing_event {} is neither 0 nor 1", flag));
  return flag == 1.0;
}

// A row's correction: six numbers, or six empty cells (none); a row with
// some would leave the others' at zero, a wrong nominal residual.
void ReadCorrection(const RowParser& p, const CsvColumns& columns, MeasurementRow* row) {
  int given = 0;
  for (int k = 0; k < 6; ++k) {
    double c = 0.0;
    if (p.OptionalNumber(columns.leg_corr[k], "leg_corr", &c)) {
      row->leg_corr_m(k) = c;
      ++given;
    }
  }
  if (given == 0 || given == 6) return;
  for (int k = 0; k < 6; ++k) {
    double c = 0.0;
    if (!p.OptionalNumber(columns.leg_corr[k], "leg_corr", &c)) {
      p.Fail(columns.leg_corr[k], "leg_corr", fmt::format("leg_corr_{}_m is empty beside {} given", k + 1, given));
    }
  }
}

}  // namespace

MeasurementData ParseMeasurementCsv(const std::string& text, const std::string& origin, TimingEvents timing) {
  MeasurementData data;
  data.source = origin;
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  CsvColumns columns;
  bool have_header = false;
  std::map<std::string, int> run_index;
  std::map<int, double> last_time;
  while (std::getline(in, line)) {
    ++line_number;
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    const std::vector<Field> fields = SplitCsvLine(line);
    if (!have_header) {
      columns = FindColumns(fields, origin, line_number);
      data.has_correction = columns.leg_corr[0] >= 0;
      have_header = true;
      continue;
    }
    const RowParser p(origin, line_number, fields);
    if (FlaggedTimingEvent(p, columns.timing_event)) {
      if (timing == TimingEvents::kLeaveOut) {
        ++data.timing_excluded;
        continue;
      }
      ++data.timing_kept;
    }
    MeasurementRow row;
    row.time_s = p.Number(columns.time, "time_s");
    const std::string run = p.Text(columns.run, "run");
    const auto [it, added] = run_index.emplace(run, static_cast<int>(data.runs.size()));
    if (added) data.runs.push_back(run);
    row.run = it->second;
    const char* pose_names[6] = {"pose_cmd_x_m",      "pose_cmd_y_m",       "pose_cmd_z_m",
                                 "pose_cmd_roll_rad", "pose_cmd_pitch_rad", "pose_cmd_yaw_rad"};
    for (int k = 0; k < 6; ++k) row.pose_cmd(k) = p.Number(columns.pose[k], pose_names[k]);
    for (int k = 0; k < 6; ++k) row.leg_cmd_m(k) = p.Number(columns.leg_cmd[k], "leg_cmd");
    row.has_encoder = columns.has_encoder;
    for (int k = 0; k < 6 && row.has_encoder; ++k) {
      row.has_encoder = p.OptionalNumber(columns.leg_enc[k], "leg_enc", &row.leg_enc_m(k));
    }
    if (columns.leg_corr[0] >= 0) ReadCorrection(p, columns, &row);
    const char* point_names[3] = {"point_x_m", "point_y_m", "point_z_m"};
    for (int k = 0; k < 3; ++k) row.point_m(k) = p.Number(columns.point[k], point_names[k]);
    const auto previous = last_time.find(row.run);
    if (previous != last_time.end() && row.time_s < previous->second) {
      throw MeasurementError(fmt::format("{}:{}:{}: time_s {} goes back in run \"{}\" (previous {})", origin,
                                         line_number, fields[static_cast<std::size_t>(columns.time)].column, row.time_s,
                                         run, previous->second));
    }
    last_time[row.run] = row.time_s;
    data.rows.push_back(row);
  }
  if (!have_header) throw MeasurementError(origin + ": no header row (empty file?)");
  if (data.rows.empty()) {
    throw MeasurementError(
        data.timing_excluded > 0
            ? fmt::format("{}: every one of its {} rows is flagged timing_event", origin, data.timing_excluded)
            : origin + ": a header but no data rows");
  }
  return data;
}

MeasurementData LoadMeasurement(const std::string& path, TimingEvents timing) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw MeasurementError(path + ": cannot open");
  unsigned char magic[4] = {0, 0, 0, 0};
  file.read(reinterpret_cast<char*>(magic), 4);
  // LCM log events start with the sync word 0xEDA1DA01.
  if (file.gcount() == 4 && magic[0] == 0xED && magic[1] == 0xA1 && magic[2] == 0xDA && magic[3] == 0x01) {
    std::ostringstream csv;
    const MeasurementExport exported = ExportMeasurementCsv(path, csv);
    if (exported.rows == 0) throw MeasurementError(path + ": the log has no tracker samples with commands");
    MeasurementData data = ParseMeasurementCsv(csv.str(), path + " (exported)", timing);
    data.source = path;
    return data;
  }
  file.seekg(0);
  std::ostringstream text;
  text << file.rdbuf();
  return ParseMeasurementCsv(text.str(), path, timing);
}

void AppendMeasurement(MeasurementData* data, MeasurementData more) {
  if (data->rows.empty()) {
    *data = std::move(more);
    return;
  }
  const std::set<std::string> existing(data->runs.begin(), data->runs.end());
  const int offset = static_cast<int>(data->runs.size());
  const std::string suffix = "@" + more.source.substr(more.source.rfind('/') + 1);
  for (const std::string& run : more.runs) data->runs.push_back(existing.count(run) ? run + suffix : run);
  for (MeasurementRow& row : more.rows) {
    row.run += offset;
    data->rows.push_back(row);
  }
  data->timing_excluded += more.timing_excluded;
  data->timing_kept += more.timing_kept;
  data->has_correction = data->has_correction || more.has_correction;
  data->source += ", " + more.source;
}

MeasurementData Decimated(const MeasurementData& data, double max_rate_hz) {
  MeasurementData out;
  out.runs = data.runs;
  out.source = data.source;
  out.timing_excluded = data.timing_excluded;
  out.timing_kept = data.timing_kept;
  out.has_correction = data.has_correction;
  std::map<int, double> last_kept;
  const double min_spacing = 1.0 / max_rate_hz - 1e-9;
  for (const MeasurementRow& row : data.rows) {
    const auto it = last_kept.find(row.run);
    if (it != last_kept.end() && row.time_s - it->second < min_spacing) continue;
    last_kept[row.run] = row.time_s;
    out.rows.push_back(row);
  }
  return out;
}

}  // namespace edsp::gap
