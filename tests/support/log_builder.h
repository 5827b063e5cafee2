#pragma once
// Writes LCM log files event by event for the logger tests: edsp messages,
// raw bytes (foreign or truncated packets), timestamps 1 ms apart.

#include <cstdint>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "encoded.h"

namespace edsp::test_support {

class LogBuilder {
 public:
  explicit LogBuilder(const std::string& path) : log_(path, "w") {}
  template <typename Msg>
  void Add(const std::string& channel, const Msg& msg) {
    AddBytes(channel, Encoded(msg));
  }
  void AddBytes(const std::string& channel, std::vector<std::uint8_t> bytes) {
    lcm::LogEvent e{};
    e.eventnum = n_++;
    e.timestamp = 1000 * n_;
    e.channel = channel;
    e.datalen = static_cast<std::int32_t>(bytes.size());
    e.data = bytes.data();
    log_.writeEvent(&e);
  }

 private:
  lcm::LogFile log_;
  std::int64_t n_ = 0;
};

}  // namespace edsp::test_support
