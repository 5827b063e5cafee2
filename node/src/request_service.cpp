#include "edsp/node/request_service.h"

#include <cmath>

#include <fmt/format.h>

namespace edsp {

Refusal AddressProblem(const RequestPolicy& policy, std::int64_t session_id, std::int64_t request_id,
                       std::int64_t utime, std::int64_t now_utime, std::int64_t acted_utime) {
  if (session_id != policy.session_id) {
    return {ReplyCode::kOtherSession, fmt::format("request {} from session {} ignored: this group is session {}",
                                                  request_id, session_id, policy.session_id)};
  }
  if (request_id == 0) return {ReplyCode::kInvalid, "request_id 0: give each request a unique non-zero id"};
  const double age_s = (static_cast<double>(now_utime) - static_cast<double>(utime)) * 1e-6;
  if (!(std::abs(age_s) <= policy.window_s)) {
    return {ReplyCode::kStale,
            fmt::format("request {} stamped {:.1f} s {} this node's clock ignored (a replayed "
                        "log, or a clock off by more than {} s)",
                        request_id, std::abs(age_s), age_s > 0 ? "before" : "after", policy.window_s)};
  }
  if (policy.refuse_older_than_acted && utime < acted_utime) {
    return {ReplyCode::kStale,
            fmt::format("request {} stamped {:.3f} s before the last one acted on ignored: a late "
                        "request does not undo a later one",
                        request_id, (static_cast<double>(acted_utime) - static_cast<double>(utime)) * 1e-6)};
  }
  return {};
}

}  // namespace edsp
