#pragma once
// One CSV per channel from an edsp log, for any tool that reads CSV: every
// field of every message edsp knows, arrays flattened (pose_1 … pose_6,
// base_joints_m_1_1 … _6_3), text quoted, doubles to 17 significant digits so
// nothing is lost. A channel's type is that of its first decodable message;
// anything else on it (a foreign type, a truncated packet) is counted, not
// written.

#include <cstdint>
#include <map>
#include <string>

namespace edsp {

struct ChannelCsv {
  std::string path;
  std::string type;  // e.g. "edsp.pose_setpoint_t"
  std::int64_t rows = 0;
  std::int64_t skipped = 0;  // undecodable or of another type
};

struct ChannelCsvExport {
  std::map<std::string, ChannelCsv> channels;   // only channels with a decodable message
  std::map<std::string, std::int64_t> unknown;  // channels edsp cannot decode: messages
  bool damaged = false;
  std::int64_t damage_offset = -1;
};

// Writes <out_dir>/<CHANNEL>.csv for each channel matching `channel_regex`
// (ECMAScript, whole name). Creates out_dir. Throws std::runtime_error naming
// the log, the directory or the file on failure, and for a bad regex.
ChannelCsvExport ExportChannelCsvs(const std::string& log_path, const std::string& out_dir,
                                   const std::string& channel_regex = ".*");

}  // namespace edsp
