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
  if constexpr (std::is_same_v<T, std::int8_t>) return ColumnKind::kInt8;
  else if constexpr (std::is_same_v<T, std::int32_t>) return ColumnKind::kInt32;
  else if constexpr (std::is_same_v<T, std::int64_t>) return ColumnKind::kInt64;
  else if constexpr (std::is_same_v<T, double>) return ColumnKind::kDouble;
  else {
    static_assert(std::is_same_v<T, std::string>, "a field type the columns do not know");
    return ColumnKind::kText;
  }
}

template <typename T>
std::vector<std::size_t> ShapeOf() {
  std::vector<std::size_t> shape;
  if constexpr (std::rank_v<T> > 0) {
    shape.push_back(std::extent_v<T>);
    for (std::size_t n : ShapeOf<std::remove_extent_t<T>>()) shape.push_back(n);
  }
  return shape;
}

// A message's fields appended as one row: the columns are made by the
// table's first message and filled in the same order by every later one.
class RowAppender {
 public:
  // `expected_rows`: the table's length when known, for its new columns.
  RowAppender(std::vector<Column>* columns, std::int64_t expected_rows)
      : columns_(columns), creating_(columns->empty()), expected_rows_(static_cast<std::size_t>(expected_rows)) {}

  template <typename T>
  void Add(const char* name, const T& value) {
    using Element = std::remove_all_extents_t<T>;
    Column& column = Next<T>(name);
    if constexpr (std::is_same_v<Element, std::string>) {
      static_assert(std::rank_v<T> == 0, "arrays of text are not in any edsp type");
      column.text.push_back(value);
    } else {
      const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);  // arrays are contiguous
      column.values.insert(column.values.end(), bytes, bytes + sizeof(T));
    }
  }

 private:
  template <typename T>
  Column& Next(const char* name) {
    if (!creating_) return (*columns_)[next_++];
    Column column;
    column.name = name;
    column.kind = KindOf<std::remove_all_extents_t<T>>();
    column.shape = ShapeOf<T>();
    if constexpr (std::is_same_v<std::remove_all_extents_t<T>, std::string>) column.text.reserve(expected_rows_);
    else column.values.reserve(expected_rows_ * sizeof(T));
    columns_->push_back(std::move(column));
    return columns_->back();
  }

  std::vector<Column>* columns_;
  bool creating_;
  std::size_t expected_rows_;
  std::size_t next_ = 0;
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
      void* data = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
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
    if (table == nullptr) {
      table = &channels_[std::string(channel)];
      table->type = type;
      const auto unknown = unknown_.find(channel);  // what came before it
      if (unknown != unknown_.end()) table->skipped = unknown->second, unknown_.erase(unknown);
      const auto expected = expected_.find(channel);
      if (expected != expected_.end()) table->receive_utime.reserve(static_cast<std::size_t>(expected->second));
    } else if (table->type != type) {
      return;  // a channel keeps its first type
    }
    RowAppender row(&table->columns, static_cast<std::int64_t>(table->receive_utime.capacity()));
    VisitFields(msg, &row);
    table->receive_utime.push_back(receive_utime);
    kept = true;
  });
  if (kept) return;
  if (table != nullptr) {
    ++table->skipped;
  } else {
    const auto unknown = unknown_.find(channel);
    if (unknown != unknown_.end()) ++unknown->second;
    else unknown_.emplace(std::string(channel), 1);
  }
}

ChannelColumns EmptyColumns(const std::string& type_name) {
  ChannelColumns table;
  ForEachMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    const std::string name = Msg::getTypeName();
    if (!table.type.empty() || (type_name != name && type_name != "edsp." + name)) return;
    table.type = "edsp." + name;
    RowAppender row(&table.columns, 1);
    VisitFields(Msg{}, &row);
  });
  if (table.type.empty()) throw std::invalid_argument(type_name + ": not an edsp message type");
  for (Column& column : table.columns) column.values.clear(), column.text.clear();
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
  for (const auto& [channel, n] : counts) {
    if (n > 0) out.messages.Expect(channel, n);
  }
  out.damage_offset = ForEachEvent(file, [&](std::string_view channel, const std::uint8_t* data, std::size_t size,
                                             std::int64_t utime) {
    // A channel the count did not see (the file changed under the mapping) is left out.
    const auto counted = counts.find(channel);
    if (counted != counts.end() && counted->second >= 0) out.messages.Add(channel, data, size, utime);
  });
  out.damaged = out.damage_offset >= 0;
  return out;
}

}  // namespace edsp
