#include "edsp/logger/message_columns.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "edsp/logger/edsp_message.h"
#include "edsp/logger/lcm_log_format.h"

namespace edsp {

namespace {

template <typename T>
constexpr ColumnKind KindOf() {
  if constexpr (std::is_same_v<T, std::int8_t>)
    return ColumnKind::kInt8;
  else if constexpr (std::is_same_v<T, std::int32_t>)
    return ColumnKind::kInt32;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return ColumnKind::kInt64;
  else if constexpr (std::is_same_v<T, double>)
    return ColumnKind::kDouble;
  else {
    static_assert(std::is_same_v<T, std::string>, "a field type the columns do not know");
    return ColumnKind::kText;
  }
}

template <typename T>
std::vector<std::size_t> ShapeOf() {
  std::vector<std::size_t> shape;
  if constexpr (std::rank_v < T >> 0) {
    shape.push_back(std::extent_v<T>);
    for (std::size_t n : ShapeOf<std::remove_extent_t<T>>()) shape.push_back(n);
  }
  return shape;
}

std::size_t AlignUp(std::size_t at, std::size_t alignment) { return (at + alignment - 1) / alignment * alignment; }

// The row layout of a type: each field's column at its natural alignment.
class Layout {
 public:
  explicit Layout(std::vector<Column>* columns) : columns_(columns) {
    Place("receive_utime", ColumnKind::kInt64, {}, sizeof(std::int64_t), alignof(std::int64_t));
  }

  template <typename T>
  void Add(const char* name, const T&) {
    using Element = std::remove_all_extents_t<T>;
    if constexpr (std::is_same_v<Element, std::string>) {
      static_assert(std::rank_v<T> == 0, "arrays of text are not in any edsp type");
      Place(name, ColumnKind::kText, {}, sizeof(void*), alignof(void*));
    } else {
      Place(name, KindOf<Element>(), ShapeOf<T>(), sizeof(T), alignof(Element));
    }
  }

  // The row's size: numpy's aligned struct pads to its widest member.
  std::size_t row_bytes() const { return AlignUp(end_, 8); }

 private:
  void Place(const char* name, ColumnKind kind, std::vector<std::size_t> shape, std::size_t bytes,
             std::size_t alignment) {
    Column column;
    column.name = name, column.kind = kind, column.shape = std::move(shape);
    column.offset = AlignUp(end_, alignment);
    column.bytes = bytes;
    end_ = column.offset + bytes;
    columns_->push_back(std::move(column));
  }

  std::vector<Column>* columns_;
  std::size_t end_ = 0;
};

template <typename Msg>
void MakeLayout(ChannelColumns* table) {
  Layout layout(&table->columns);
  VisitFields(Msg{}, &layout);
  table->row_bytes = layout.row_bytes();
}

// A message's fields written into its row, in the layout's order.
class RowWriter {
 public:
  RowWriter(std::vector<Column>* columns, std::uint8_t* row) : columns_(columns), row_(row) {}

  template <typename T>
  void Add(const char*, const T& value) {
    Column& column = (*columns_)[next_++];
    if constexpr (std::is_same_v<std::remove_all_extents_t<T>, std::string>) {
      column.text.push_back(value);
    } else {
      std::memcpy(row_ + column.offset, &value, sizeof(T));  // arrays are contiguous, row-major
    }
  }

 private:
  std::vector<Column>* columns_;
  std::uint8_t* row_;
  std::size_t next_ = 1;  // after receive_utime
};

// A file mapped read-only for the life of the object.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(path + ": cannot open as an LCM log (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
      ::close(fd);
      throw std::runtime_error(path + ": cannot read as an LCM log");
    }
    size_ = static_cast<std::size_t>(st.st_size);
    if (size_ > 0) {
      void* data = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);  // read ahead at once
      if (data == MAP_FAILED) {
        ::close(fd);
        throw std::runtime_error(path + ": cannot map as an LCM log");
      }
      data_ = static_cast<const std::uint8_t*>(data);
    }
    ::close(fd);
  }
  ~MappedFile() {
    if (data_ != nullptr) ::munmap(const_cast<std::uint8_t*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  const std::uint8_t* data() const { return data_; }
  std::size_t size() const { return size_; }

 private:
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
};

// f(channel, data, size, utime) for every whole event from the start;
// returns where the first bytes that are not one begin (the damage), or -1.
template <typename F>
std::int64_t ForEachEvent(const MappedFile& file, F&& f) {
  const std::int64_t size = static_cast<std::int64_t>(file.size());
  std::int64_t at = 0;
  while (at < size) {
    lcm_log::EventHeader header;
    if (size - at < static_cast<std::int64_t>(lcm_log::kHeaderBytes) ||
        !lcm_log::ParseEventHeader(file.data() + at, size - at, &header)) {
      return at;
    }
    const std::uint8_t* channel = file.data() + at + lcm_log::kHeaderBytes;
    f(std::string_view(reinterpret_cast<const char*>(channel), static_cast<std::size_t>(header.channel_bytes)),
      channel + header.channel_bytes, static_cast<std::size_t>(header.data_bytes), header.timestamp_utime);
    at += header.total_bytes();
  }
  return -1;
}

}  // namespace

void MessageColumns::Expect(std::string_view channel, std::int64_t messages) {
  expected_[std::string(channel)] = messages;
}

void MessageColumns::Add(std::string_view channel, const std::uint8_t* data, std::size_t size,
                         std::int64_t receive_utime) {
  const auto found = channels_.find(channel);
  ChannelColumns* table = found == channels_.end() ? nullptr : &found->second;
  bool kept = false;
  DecodeEdspMessage(data, size, [&](const auto& msg, const std::string& type) {
    using Msg = std::decay_t<decltype(msg)>;
    if (table == nullptr) {
      table = &channels_[std::string(channel)];
      table->type = type;
      MakeLayout<Msg>(table);
      const auto unknown = unknown_.find(channel);  // what came before it
      if (unknown != unknown_.end()) table->skipped = unknown->second, unknown_.erase(unknown);
      const auto expected = expected_.find(channel);
      if (expected != expected_.end()) {
        table->rows_data.reserve(static_cast<std::size_t>(expected->second) * table->row_bytes);
        for (Column& column : table->columns) {
          if (column.kind == ColumnKind::kText) column.text.reserve(static_cast<std::size_t>(expected->second));
        }
      }
    } else if (table->type != type) {
      return;  // a channel keeps its first type
    }
    const std::size_t at = table->rows_data.size();
    table->rows_data.resize(at + table->row_bytes);  // zero: padding and text slots
    std::uint8_t* row = table->rows_data.data() + at;
    std::memcpy(row, &receive_utime, sizeof receive_utime);
    RowWriter writer(&table->columns, row);
    VisitFields(msg, &writer);
    kept = true;
  });
  if (kept) return;
  if (table != nullptr) {
    ++table->skipped;
  } else {
    const auto unknown = unknown_.find(channel);
    if (unknown != unknown_.end())
      ++unknown->second;
    else
      unknown_.emplace(std::string(channel), 1);
  }
}

ChannelColumns EmptyColumns(const std::string& type_name) {
  ChannelColumns table;
  ForEachMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    const std::string name = Msg::getTypeName();
    if (!table.type.empty() || (type_name != name && type_name != "edsp." + name)) return;
    table.type = "edsp." + name;
    MakeLayout<Msg>(&table);
  });
  if (table.type.empty()) throw std::invalid_argument(type_name + ": not an edsp message type");
  return table;
}

LogColumns ReadLogColumns(const std::string& path, const std::function<bool(const std::string&)>& wanted) {
  const MappedFile file(path);
  std::map<std::string, std::int64_t, std::less<>> counts;  // and whether wanted: -1 not
  ForEachEvent(file, [&](std::string_view channel, const std::uint8_t*, std::size_t, std::int64_t) {
    auto found = counts.find(channel);
    if (found == counts.end()) {
      const std::string name(channel);
      found = counts.emplace(name, wanted(name) ? 0 : -1).first;
    }
    if (found->second >= 0) ++found->second;
  });
  LogColumns out;
  bool every_channel = true;  // then no lookup per event: the usual read of a whole log
  for (const auto& [channel, n] : counts) {
    if (n > 0) out.messages.Expect(channel, n);
    every_channel = every_channel && n >= 0;
  }
  out.damage_offset =
      ForEachEvent(file, [&](std::string_view channel, const std::uint8_t* data, std::size_t size, std::int64_t utime) {
        // With a filter, a channel the count did not see (the file changed under the mapping) is left out.
        const auto counted = every_channel ? counts.end() : counts.find(channel);
        if (every_channel || (counted != counts.end() && counted->second >= 0))
          out.messages.Add(channel, data, size, utime);
      });
  out.damaged = out.damage_offset >= 0;
  return out;
}

}  // namespace edsp
