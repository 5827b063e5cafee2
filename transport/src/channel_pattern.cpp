#include "edsp/transport/channel_pattern.h"

#include <fmt/format.h>

#include "edsp/transport/error.h"

namespace edsp {

ChannelPattern::ChannelPattern(const std::string& pattern) : pattern_(pattern) {
  const int error = ::regcomp(&compiled_, ("^(" + pattern + ")$").c_str(), REG_EXTENDED | REG_NOSUB);
  if (error != 0) {
    char what[256];
    ::regerror(error, &compiled_, what, sizeof what);
    throw TransportError(fmt::format("channel pattern '{}' is not a POSIX extended regex: {}", pattern, what));
  }
}

ChannelPattern::~ChannelPattern() { ::regfree(&compiled_); }

bool ChannelPattern::Matches(const std::string& channel) const {
  return ::regexec(&compiled_, channel.c_str(), 0, nullptr, 0) == 0;
}

}  // namespace edsp
