// edsp.read_log and Platform.record's core: LCM logs and live recordings
// decoded in C++ into one column per field (logger/message_columns.h),
// which python/edsp/_data.py assembles into numpy structured arrays.
#include <pybind11/stl.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "bindings.h"
#include "edsp/channels.h"
#include "edsp/logger/bus_recording.h"
#include "edsp/logger/message_columns.h"
#include "edsp/node/group_file.h"
#include "edsp/setpoint_phases.h"
#include "edsp/transport/transport_config.h"

namespace edsp::python {

namespace {

const char* CodeOf(ColumnKind kind) {
  switch (kind) {
    case ColumnKind::kInt8: return "i1";
    case ColumnKind::kInt32: return "i4";
    case ColumnKind::kInt64: return "i8";
    case ColumnKind::kDouble: return "f8";
    case ColumnKind::kText: return "O";
  }
  return "O";
}

// Text as sent; bytes that are not UTF-8 (a foreign or damaged sender) as U+FFFD.
py::str Text(const std::string& s) {
  PyObject* text = PyUnicode_DecodeUTF8(s.data(), static_cast<Py_ssize_t>(s.size()), "replace");
  if (text == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(text);
}

// The table's row layout as a numpy dtype: the same names, offsets and size.
py::dtype DtypeOf(const ChannelColumns& table) {
  py::list names, formats, offsets;
  for (const Column& column : table.columns) {
    std::string shape;
    for (std::size_t n : column.shape) shape += (shape.empty() ? "(" : ",") + std::to_string(n);
    if (column.shape.size() == 1) shape += ",";  // "(6,)": a 1-tuple
    if (!shape.empty()) shape += ")";
    names.append(column.name);
    formats.append(shape + CodeOf(column.kind));
    offsets.append(column.offset);
  }
  py::dict spec;
  spec["names"] = names, spec["formats"] = formats, spec["offsets"] = offsets;
  spec["itemsize"] = table.row_bytes;
  return py::dtype::from_args(spec);
}

// The rows a structured array shows without a copy (read_log's memory is
// the log's size again, not twice), and the strs in its text slots: numpy
// frees neither for memory it does not own, this does when the array goes.
struct RowsHolder {
  std::vector<std::uint8_t> rows;
  std::vector<std::size_t> text_offsets;
  std::size_t row_bytes = 0;

  ~RowsHolder() {
    for (std::size_t at = 0; row_bytes > 0 && at < rows.size(); at += row_bytes) {
      for (std::size_t offset : text_offsets) {
        PyObject* text = nullptr;
        std::memcpy(&text, rows.data() + at + offset, sizeof text);
        Py_XDECREF(text);
      }
    }
  }
};

// (type, skipped, structured array over the table's rows, its text filled in).
py::tuple Table(ChannelColumns&& table) {
  const py::ssize_t rows = table.rows();
  auto holder = std::make_unique<RowsHolder>();
  holder->row_bytes = table.row_bytes;
  holder->rows = std::move(table.rows_data);
  if (holder->rows.empty()) holder->rows.resize(table.row_bytes);  // a pointer numpy can keep
  for (Column& column : table.columns) {
    if (column.kind != ColumnKind::kText) continue;
    holder->text_offsets.push_back(column.offset);
    for (py::ssize_t row = 0; row < rows; ++row) {
      PyObject* text = Text(column.text[static_cast<std::size_t>(row)]).release().ptr();  // the holder owns it
      std::memcpy(holder->rows.data() + static_cast<std::size_t>(row) * table.row_bytes + column.offset, &text,
                  sizeof text);
    }
  }
  std::uint8_t* data = holder->rows.data();
  const py::capsule owner(holder.release(), [](void* p) { delete static_cast<RowsHolder*>(p); });
  py::array out(DtypeOf(table), std::vector<py::ssize_t>{rows}, data, owner);
  return py::make_tuple(table.type, table.skipped, out);
}

py::dict Tables(MessageColumns&& messages) {
  py::dict out;
  for (auto& [channel, table] : messages.channels()) out[Text(channel)] = Table(std::move(table));
  return out;
}

// ({channel: table}, {"unknown": {channel: count}, "damaged": bool, "damage_offset": int}).
py::tuple ReadLog(const std::string& path, const std::optional<std::vector<std::string>>& channels) {
  const std::set<std::string> wanted =
      channels ? std::set<std::string>(channels->begin(), channels->end()) : std::set<std::string>{};
  LogColumns log;
  {
    py::gil_scoped_release release;
    log = ReadLogColumns(path, [&](const std::string& c) { return !channels || wanted.count(c) > 0; });
  }
  py::dict info;
  py::dict unknown;  // names from a damaged or foreign log: not necessarily UTF-8
  for (const auto& [channel, count] : log.messages.unknown()) unknown[Text(channel)] = count;
  info["unknown"] = unknown;
  info["damaged"] = log.damaged;
  info["damage_offset"] = log.damage_offset;
  return py::make_tuple(Tables(std::move(log.messages)), info);
}

py::tuple EmptyTable(const std::string& type_name) { return Table(EmptyColumns(type_name)); }

// A POSIX extended regex matching exactly these channel names.
std::string PatternOf(const std::vector<std::string>& channels) {
  std::string pattern;
  for (const std::string& name : channels) {
    if (!pattern.empty()) pattern += '|';
    for (char c : name) {
      if (std::string(".[]{}()\\*+?^$|").find(c) != std::string::npos) pattern += '\\';
      pattern += c;
    }
  }
  return pattern;
}

class Recording {
 public:
  Recording(const std::string& group_file, const std::string& lcm_url, const std::vector<std::string>& channels,
            std::int64_t max_bytes)
      : recording_(Transport(group_file, lcm_url), PatternOf(channels), max_bytes) {}

  void Stop() {
    py::gil_scoped_release release;
    recording_.Stop();
  }
  py::dict Stats() const {
    const BusRecordingStats s = recording_.stats();
    py::dict d;
    d["messages"] = s.messages, d["bytes"] = s.bytes, d["dropped"] = s.dropped, d["overruns"] = s.overruns;
    d["error"] = s.error;
    return d;
  }
  py::dict Columns() const {
    MessageColumns columns;
    {
      py::gil_scoped_release release;
      columns = recording_.Columns();
    }
    return Tables(std::move(columns));
  }
  void Save(const std::string& path) const {
    py::gil_scoped_release release;
    recording_.Save(path);
  }

 private:
  // The group's own routes: a channel it carries on shared memory is read there, whole.
  static TransportConfig Transport(const std::string& group_file, const std::string& lcm_url) {
    TransportConfig config = group_file.empty() ? TransportConfig{} : LoadTransportConfig(group_file);
    if (!lcm_url.empty()) config.lcm_url = lcm_url;
    return config;
  }

  BusRecording recording_;
};

}  // namespace

void BindData(py::module_& m) {
  m.def("read_log", &ReadLog, py::arg("path"), py::arg("channels"));
  m.def("empty_table", &EmptyTable, py::arg("type_name"));
  py::dict channels;
  for (const channel::Channel& c : channel::kChannels) channels[py::str(std::string(c.name))] = std::string(c.type);
  m.attr("CHANNELS") = channels;
  // name (upper-cased) -> pose_setpoint_t.PHASE_*: edsp.SetpointPhase is made from it.
  py::dict phases;
  for (const SetpointPhaseRow& row : kSetpointPhases) {
    std::string name(row.name);
    for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    phases[py::str(name)] = static_cast<int>(row.phase);
  }
  m.attr("SETPOINT_PHASES") = phases;
  py::class_<Recording>(m, "Recording")
      .def(py::init<const std::string&, const std::string&, const std::vector<std::string>&, std::int64_t>(),
           py::arg("group_file"), py::arg("lcm_url"), py::arg("channels"), py::arg("max_bytes"))
      .def("stop", &Recording::Stop)
      .def("stats", &Recording::Stats)
      .def("columns", &Recording::Columns)
      .def("save", &Recording::Save, py::arg("path"));
}

}  // namespace edsp::python
