#pragma once
// Messages decoded into tables, one per channel, already in the row layout
// of a numpy structured array (the Python package's read_log and recorder
// hand it to numpy in one copy): per row, the time the message was received
// (the log's event stamp) first, then every field of the channel's type
// (message_fields.h) in field order, each at its natural alignment; a
// fixed-size array field is one column of that shape; text is kept beside,
// its slot in the row left zero (numpy's object pointer goes there). A
// channel's type is that of its first decodable message; anything else on
// it is counted, not kept.

#include <cstddef>
#include <cstdint>
#include <cstring>
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
  std::vector<std::size_t> shape;  // of one row's value: {} a scalar, {6}, {6, 3}
  std::size_t offset = 0;          // in the row
  std::size_t bytes = 0;           // of one row's value (text: the 8-byte slot)
  std::vector<std::string> text;   // kText: one per row
};

struct ChannelColumns {
  std::string type;                     // "edsp.leg_state_t"
  std::vector<Column> columns;          // receive_utime, then the type's fields
  std::size_t row_bytes = 0;            // a multiple of 8
  std::vector<std::uint8_t> rows_data;  // row after row, native byte order
  std::int64_t skipped = 0;             // of another type, or undecodable

  std::int64_t rows() const { return row_bytes == 0 ? 0 : static_cast<std::int64_t>(rows_data.size() / row_bytes); }
  // Element `element` (row-major within an array field) of `column` in `row`.
  template <typename T>
  T Value(std::int64_t row, std::size_t column, std::size_t element = 0) const {
    T value;
    std::memcpy(
        &value,
        rows_data.data() + static_cast<std::size_t>(row) * row_bytes + columns[column].offset + element * sizeof(T),
        sizeof(T));
    return value;
  }
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
  bool damaged = false;  // the log ends in damage; what came before is read
  std::int64_t damage_offset = -1;
};

// Every message of the log at `path` on a channel `wanted` accepts, up to
// the first bytes that are not a whole event (as LogReader reads it; the
// file mapped and read in place, counted first, at hundreds of MB/s).
// Throws std::runtime_error naming a file that cannot be opened.
LogColumns ReadLogColumns(const std::string& path, const std::function<bool(const std::string&)>& wanted);

}  // namespace edsp
