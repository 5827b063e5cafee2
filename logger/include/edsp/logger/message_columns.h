#pragma once
// Messages decoded into columns, a table per channel, for numpy's
// structured arrays (the Python package's read_log and recorder): one column
// per field of the channel's type (message_fields.h), in field order, with
// the time the message was received (the log's event stamp) first. A
// fixed-size array field is one column of that shape per row; text is a
// column of strings. A channel's type is that of its first decodable
// message; anything else on it is counted, not kept.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace edsp {

enum class ColumnKind { kInt8, kInt32, kInt64, kDouble, kText };

struct Column {
  std::string name;
  ColumnKind kind = ColumnKind::kDouble;
  std::vector<std::size_t> shape;    // of one row's value: {} a scalar, {6}, {6, 3}
  std::vector<std::uint8_t> values;  // numbers, row after row, native byte order
  std::vector<std::string> text;     // kText: one per row
};

struct ChannelColumns {
  std::string type;                  // "edsp.leg_state_t"
  std::vector<std::int64_t> receive_utime;  // per row: the log's event stamp
  std::vector<Column> columns;       // the type's fields, in order
  std::int64_t rows() const { return static_cast<std::int64_t>(receive_utime.size()); }
  std::int64_t skipped = 0;          // of another type, or undecodable
};

class MessageColumns {
 public:
  // One message as received on `channel` at `receive_utime`.
  void Add(std::string_view channel, const std::uint8_t* data, std::size_t size, std::int64_t receive_utime);
  // How many messages `channel` will have (a log counted first): its
  // columns are made that long at once, not grown message by message.
  void Expect(std::string_view channel, std::int64_t messages);

  const std::map<std::string, ChannelColumns, std::less<>>& channels() const { return channels_; }
  std::map<std::string, ChannelColumns, std::less<>>& channels() { return channels_; }
  // Channels none of whose messages edsp can decode: how many came.
  const std::map<std::string, std::int64_t, std::less<>>& unknown() const { return unknown_; }

 private:
  std::map<std::string, ChannelColumns, std::less<>> channels_;
  std::map<std::string, std::int64_t, std::less<>> unknown_;
  std::map<std::string, std::int64_t, std::less<>> expected_;
};

// The columns, without rows, of the edsp type named "edsp.<type>" or
// "<type>" (a channel asked for that carried nothing). Throws
// std::invalid_argument naming an unknown type.
ChannelColumns EmptyColumns(const std::string& type_name);

struct LogColumns {
  MessageColumns messages;
  bool damaged = false;             // the log ends in damage; what came before is read
  std::int64_t damage_offset = -1;
};

// Every message of the log at `path` on a channel `wanted` accepts, up to
// the first bytes that are not a whole event (as LogReader reads it; the
// file mapped and read in place, counted first, at hundreds of MB/s).
// Throws std::runtime_error naming a file that cannot be opened.
LogColumns ReadLogColumns(const std::string& path, const std::function<bool(const std::string&)>& wanted);

}  // namespace edsp
