#include "edsp/logger/channel_csv_export.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "edsp/logger/edsp_message.h"
#include "edsp/logger/log_reader.h"

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
    throw std::runtime_error("--channels '" + channel_regex + "': not a regular expression (" + e.what() + ")");
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
    CsvRow row;
    std::string type;
    const bool decoded = DecodeEdspMessage(event.data.data(), event.data.size(),
                                           [&](const auto& msg, std::string name) {
                                             if (file && file->info.type != name)
                                               return;  // a channel keeps its first type
                                             VisitFields(msg, &row);
                                             type = std::move(name);
                                           }) &&
                         !type.empty();
    if (!decoded) {
      if (file)
        ++file->info.skipped;
      else
        ++result.unknown[event.channel];
      if (!file) files.erase(event.channel);
      continue;
    }
    if (!file) {
      file = std::make_unique<OpenCsv>();
      file->info.type = type;
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
