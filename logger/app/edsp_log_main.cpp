// edsp-log: tools for LCM log files.
//   edsp-log info LOG [--json]     channels, counts, rates, seq gaps, damage
//   edsp-log faults LOG [--node NODE,...] [--code CODE,...]
//                                  every EDSP_FAULT (or those of these nodes and codes,
//                                  codes by number or name): time, node, channel, code
//                                  (and its name), reason
//   edsp-log export --measurement FILE.csv LOG
//                                  the measurement CSV of interfaces.md §3
//   edsp-log export --csv DIR [--channels REGEX] LOG
//                                  one CSV per channel, every field
// Exit status: 0, 1 on errors, 3 when the log is damaged (what precedes the
// damage is still read and exported).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/channels.h"
#include "edsp/fault_t.hpp"
#include "edsp/logger/channel_csv_export.h"
#include "edsp/logger/log_summary.h"
#include "edsp/logger/measurement_export.h"
#include "edsp/node/fault.h"
#include "edsp/transport/decode.h"

namespace edsp {
namespace {

int Info(const std::string& path, bool json) {
  const LogSummary s = SummarizeLog(path);
  if (json) {
    nlohmann::json out;
    out["events"] = s.events;
    out["damaged"] = s.damaged;
    if (s.damaged) out["damage_offset_bytes"] = s.damage_offset;
    for (const auto& [name, c] : s.channels) {
      out["channels"][name] = {
          {"messages", c.messages},         {"bytes", c.bytes},
          {"rate_hz", c.rate_hz()},         {"seq_gaps", c.seq_gaps},
          {"seq_restarts", c.seq_restarts}, {"duration_s", static_cast<double>(c.last_utime - c.first_utime) * 1e-6}};
    }
    std::printf("%s\n", out.dump(2).c_str());
  } else {
    std::printf("%-24s %10s %10s %10s %8s\n", "channel", "messages", "rate_hz", "seq_gaps", "restarts");
    for (const auto& [name, c] : s.channels) {
      std::printf("%-24s %10lld %10.1f %10lld %8lld\n", name.c_str(), static_cast<long long>(c.messages), c.rate_hz(),
                  static_cast<long long>(c.seq_gaps), static_cast<long long>(c.seq_restarts));
    }
    if (s.damaged) {
      std::printf("damaged: read up to byte %lld, the rest is unreadable\n", static_cast<long long>(s.damage_offset));
    }
  }
  return s.damaged ? 3 : 0;
}

// Damage is not an error to stop at: what precedes it was read; say where.
int ReportDamage(const std::string& path, bool damaged, std::int64_t offset,
                 const char* done = "exported what precedes it") {
  if (!damaged) return 0;
  std::fprintf(stderr, "edsp-log: %s is damaged at byte %lld; %s\n", path.c_str(), static_cast<long long>(offset),
               done);
  return 3;
}

// Which faults `faults` lists: every one when a list is empty.
struct FaultFilter {
  std::vector<std::string> nodes;
  std::vector<std::int32_t> codes;

  bool Admits(const fault_t& f) const {
    return (nodes.empty() || std::find(nodes.begin(), nodes.end(), f.node) != nodes.end()) &&
           (codes.empty() || std::find(codes.begin(), codes.end(), f.code) != codes.end());
  }
};

std::vector<std::int32_t> FaultCodesNamed(const std::vector<std::string>& texts) {
  std::vector<std::int32_t> codes;
  for (const std::string& text : texts) {
    const std::optional<FaultCode> code = FaultCodeFromText(text);
    if (!code)
      throw std::invalid_argument(fmt::format(
          "--code {}: no such fault code (a number, or a name as edsp-log faults prints it, e.g. latched)", text));
    codes.push_back(static_cast<std::int32_t>(*code));
  }
  return codes;
}

int Faults(const std::string& path, const FaultFilter& filter) {
  LogReader reader(path);
  LogEvent event;
  std::int64_t first = -1, count = 0;
  while (reader.Next(&event)) {
    if (first < 0) first = event.timestamp_utime;
    if (event.channel != channel::kFault) continue;
    fault_t fault;
    if (!DecodeUntrusted(&fault, event.data.data(), event.data.size())) {
      std::printf("%10.3f s  (undecodable EDSP_FAULT, %zu bytes)\n",
                  static_cast<double>(event.timestamp_utime - first) * 1e-6, event.data.size());
      continue;
    }
    if (!filter.Admits(fault)) continue;
    ++count;
    std::printf("%10.3f s  %-16s %-18s code %d (%s)  %s\n", static_cast<double>(event.timestamp_utime - first) * 1e-6,
                fault.node.c_str(), fault.channel.c_str(), fault.code,
                FaultCodeName(static_cast<FaultCode>(fault.code)), fault.reason.c_str());
  }
  std::printf("%lld faults\n", static_cast<long long>(count));
  return ReportDamage(path, reader.damaged(), reader.damage_offset(), "listed the faults that precede it");
}

int ExportChannels(const std::string& path, const std::string& dir, const std::string& channels) {
  const ChannelCsvExport e = ExportChannelCsvs(path, dir, channels);
  for (const auto& [name, c] : e.channels) {
    std::fprintf(stderr, "edsp-log: %-20s %8lld rows  %s%s\n", name.c_str(), static_cast<long long>(c.rows),
                 c.path.c_str(), c.skipped ? fmt::format("  ({} undecodable skipped)", c.skipped).c_str() : "");
  }
  for (const auto& [name, n] : e.unknown) {
    std::fprintf(stderr, "edsp-log: %-20s %8lld messages of no edsp type: not exported\n", name.c_str(),
                 static_cast<long long>(n));
  }
  return ReportDamage(path, e.damaged, e.damage_offset);
}

int ExportMeasurement(const std::string& path, const std::string& csv) {
  std::ofstream out(csv);
  if (!out) throw std::runtime_error(csv + ": cannot create file");
  const MeasurementExport e = ExportMeasurementCsv(path, out);
  out.close();
  if (!out) throw std::runtime_error(csv + ": write failed");
  std::fprintf(stderr, "edsp-log: %lld rows to %s (%lld tracker samples skipped)\n", static_cast<long long>(e.rows),
               csv.c_str(), static_cast<long long>(e.skipped));
  return ReportDamage(path, e.damaged, e.damage_offset);
}

}  // namespace
}  // namespace edsp

int main(int argc, char** argv) {
  CLI::App app{"edsp-log: inspect and export LCM logs"};
  app.require_subcommand(1);
  std::string path;
  bool json = false;
  CLI::App* info = app.add_subcommand("info", "channels, counts, rates, seq gaps");
  info->add_option("log", path, "LCM log file")->required();
  info->add_flag("--json", json, "print JSON");
  CLI::App* faults = app.add_subcommand("faults", "every EDSP_FAULT with its reason");
  faults->add_option("log", path, "LCM log file")->required();
  edsp::FaultFilter fault_filter;
  std::vector<std::string> fault_codes;
  faults->add_option("--node", fault_filter.nodes, "only faults these nodes reported")->delimiter(',');
  faults->add_option("--code", fault_codes, "only these codes: numbers or names as listed (latched, drive_backend)")
      ->delimiter(',');
  CLI::App* export_cmd = app.add_subcommand("export", "export a log for analysis");
  std::string measurement, csv_dir, channels = ".*";
  export_cmd->add_option("log", path, "LCM log file")->required();
  export_cmd->add_option("--measurement", measurement, "write the measurement CSV here");
  export_cmd->add_option("--csv", csv_dir, "write one CSV per channel into this directory");
  export_cmd->add_option("--channels", channels, "with --csv: channels to export (regex)");
  export_cmd->callback([&] {
    if (measurement.empty() && csv_dir.empty()) {
      throw CLI::ValidationError("export", "give --measurement FILE and/or --csv DIR");
    }
  });
  CLI11_PARSE(app, argc, argv);
  try {
    if (*faults) {
      fault_filter.codes = edsp::FaultCodesNamed(fault_codes);
      return edsp::Faults(path, fault_filter);
    }
    if (*export_cmd) {
      int status = 0;
      if (!measurement.empty()) status = edsp::ExportMeasurement(path, measurement);
      if (!csv_dir.empty()) status = std::max(status, edsp::ExportChannels(path, csv_dir, channels));
      return status;
    }
    return edsp::Info(path, json);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "edsp-log: error: %s\n", e.what());
    return 1;
  }
}
