#pragma once
// The measurement CSV of interfaces.md §3 from an edsp log: one row per valid
// tracker sample, with the setpoint, leg command and encoder lengths most
// recently seen before it. `run` is the motion the setpoint belongs to (its
// trajectory name up to the first '/'), so hold-out splits can be by run.

#include <cstdint>
#include <ostream>
#include <string>

namespace edsp {

struct MeasurementExport {
  std::int64_t rows = 0;
  std::int64_t skipped = 0;       // tracker samples invalid or before any command
  bool damaged = false;           // the log ended in damage; rows before it are written
  std::int64_t damage_offset = -1;
};

// Throws std::runtime_error if the log cannot be opened.
MeasurementExport ExportMeasurementCsv(const std::string& log_path, std::ostream& out);

}  // namespace edsp
