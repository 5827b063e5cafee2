#pragma once
// A message's own stamp against this host's clock, as every node that takes
// commands judges it: older than the stale limit (it waited too long to
// mean anything now), or stamped in the future (the two hosts' clocks
// disagree). The stamp is the sender's word: any int64 is judged without
// overflow.

#include <cstdint>
#include <optional>
#include <string>

namespace edsp {

// Nothing when `stamp_utime` is within `limit_us` of `now_utime`; else why
// not, naming `what` ("leg command seq 12"), the age and the limit.
std::optional<std::string> StampProblem(const std::string& what, std::int64_t stamp_utime, std::int64_t now_utime,
                                        std::int64_t limit_us);

}  // namespace edsp
