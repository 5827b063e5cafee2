#pragma once
// A channel-name pattern as edsp's tools take it (edsp-logger --channels,
// edsp-log export --channels): a POSIX extended regex that must match the
// whole name, the pattern as a whole (`A|B` is A or B, never "starts with A
// or ends with B", which LCM's own ^%s$ would make of it).

#include <regex.h>

#include <string>

namespace edsp {

class ChannelPattern {
 public:
  // Throws TransportError naming the pattern and what regcomp found wrong.
  explicit ChannelPattern(const std::string& pattern);
  ~ChannelPattern();
  ChannelPattern(const ChannelPattern&) = delete;
  ChannelPattern& operator=(const ChannelPattern&) = delete;

  bool Matches(const std::string& channel) const;
  // The same set of names as LCM's pattern subscription (which wraps it in ^…$).
  std::string ForLcm() const { return "(" + pattern_ + ")"; }
  const std::string& text() const { return pattern_; }

 private:
  std::string pattern_;
  regex_t compiled_{};
};

}  // namespace edsp
