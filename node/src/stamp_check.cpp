#include "edsp/node/stamp_check.h"

#include <fmt/format.h>

namespace edsp {

std::optional<std::string> StampProblem(const std::string& what, std::int64_t stamp_utime, std::int64_t now_utime,
                                        std::int64_t limit_us) {
  // In double: exact for any real clock (below 2^53 µs), and no overflow
  // for a stamp anywhere in int64.
  const double age_us = static_cast<double>(now_utime) - static_cast<double>(stamp_utime);
  const double limit = static_cast<double>(limit_us);
  if (age_us > limit) return fmt::format("{} is {:.0f} us old (limit {} us)", what, age_us, limit_us);
  if (-age_us > limit) {
    return fmt::format(
        "{} is stamped {:.0f} us in the future (limit {} us): the clocks of its host and this "
        "one disagree (docs/multihost.md)",
        what, -age_us, limit_us);
  }
  return std::nullopt;
}

}  // namespace edsp
