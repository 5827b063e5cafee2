#pragma once
// How long a reader has watched a source stay silent. The time between two
// of the reader's looks counts up to the timing contract's feed-forward
// lapse; a longer gap is the reader's own pause (descheduled, most often
// with the whole host and the source with it), of which it saw nothing:
// counting it would blame the source for the reader's stall. A source that
// goes silent while the reader keeps its time is still found silent at the
// wall-clock rate; a reader starved for cycles finds it later, never wrongly.

#include <algorithm>
#include <cstdint>

#include "edsp/timing_contract.h"

namespace edsp {

class WatchedSilence {
 public:
  // A look that found a new message: the silence starts again from now.
  void Heard(std::int64_t now_us) {
    silent_us_ = 0;
    last_look_us_ = now_us;
  }

  // A look that found nothing: the silence watched so far, this look's gap
  // included (a first look, with none before it, counts nothing).
  std::int64_t Missed(std::int64_t now_us) {
    if (last_look_us_ >= 0) silent_us_ += std::clamp<std::int64_t>(now_us - last_look_us_, 0, kLongestWatchedGapUs);
    last_look_us_ = now_us;
    return silent_us_;
  }

  std::int64_t silent_us() const { return silent_us_; }

  static constexpr std::int64_t kLongestWatchedGapUs = timing::kFeedForwardLapseUs;

 private:
  std::int64_t last_look_us_ = -1;
  std::int64_t silent_us_ = 0;
};

}  // namespace edsp
