#include "edsp/logger/stall_watch.h"

#include <algorithm>
#include <cmath>

#include "edsp/timing_contract.h"

namespace edsp {
namespace {

// Longer than the feed-forward lapse between two readings of the drives:
// the bridge stalled, and the drives ran out of command (it stamps a stale
// image's readings with its own reads after 2 ms, so a stall of the rig
// emulator alone shows there as ~3 ms whatever its length; its own cycles
// say how long).
constexpr double kStallUs = static_cast<double>(timing::kFeedForwardLapseUs);
// Commands late while the bridge kept its time (a planner or kinematics
// tick missed) are no stall for as long as the bridge rides them through.
constexpr double kCommandsSilentUs = static_cast<double>(timing::kRideThroughUs);
// The rig emulator reports every cycle at its own instant, those it caught
// up after a late wake included (rig/physics_clock.h): two of its cycles
// further apart than 1.5 cycles lost the time between.
constexpr double kRigLateUs = 1'500;
constexpr double kFlagBeforeUs = 2'000;
// The drives' recovery: the servo's time at least, then the tracking error
// normal again for a while; at most the longest catch-up measured live.
constexpr double kSettleUs = 10'000;
constexpr double kNormalForUs = 20'000;
constexpr double kNormalFloorM = 20e-6;  // above the live rig's tracking error outside stalls (docs/figures.md)
constexpr double kNormalFactor = 2.0;    // of the largest before the stall
constexpr double kNormalLookbackUs = 50'000;
constexpr double kFlagAfterUs = 100'000;
constexpr double kFlagAfterPerStalled = 10.0;    // and 10 ms more per ms stalled,
constexpr double kLongestFlagExtensionUs = 1e6;  //   at most 1 s more (a latch)

double LatestRecovery(double from, double to) {
  return to + kFlagAfterUs + std::min(kFlagAfterPerStalled * (to - from), kLongestFlagExtensionUs);
}

// Nothing new since `since` by `newest` (0: never anything): open from it.
bool Open(double since, double newest, double t, double longest_us) {
  return since != 0.0 && newest - since > longest_us && t >= since - kFlagBeforeUs;
}

}  // namespace

void StallWatch::Reading(std::int64_t utime, std::int64_t seq) {
  if (seq == 0 || utime < newest_reading_) return;
  if (newest_reading_ != 0) Gap(newest_reading_, utime, kStallUs);
  newest_reading_ = utime;
  if (seq == command_seq_) return;
  if (command_seq_ != 0) Gap(command_since_, utime, kCommandsSilentUs);
  command_seq_ = seq;
  command_since_ = utime;
}

void StallWatch::RigCycle(std::int64_t utime) {
  if (utime <= newest_cycle_) return;
  if (newest_cycle_ != 0) Gap(newest_cycle_, utime, kRigLateUs);
  newest_cycle_ = utime;
}

void StallWatch::Heard(std::int64_t utime) { newest_heard_ = std::max(newest_heard_, utime); }

bool StallWatch::Near(std::int64_t utime, std::optional<double> tracking_error_m) {
  const double t = static_cast<double>(utime);
  if (tracking_error_m) recent_.push_back({t, *tracking_error_m});
  while (recent_.size() > 1 && t - recent_.front().utime > 2 * kNormalLookbackUs + kFlagBeforeUs) recent_.pop_front();
  while (!stalls_.empty() &&
         (stalls_.front().recovered || LatestRecovery(stalls_.front().from, stalls_.front().to) < t)) {
    stalls_.pop_front();
  }
  bool near = false;
  for (Stall& s : stalls_) near = StillNear(&s, t, tracking_error_m) || near;
  const double since_command = static_cast<double>(command_since_);
  const double newest = static_cast<double>(newest_reading_);
  return near || Open(since_command, newest, t, kCommandsSilentUs) ||
         Open(newest, static_cast<double>(newest_heard_), t, kStallUs);
}

void StallWatch::Gap(std::int64_t from, std::int64_t to, double longest_us) {
  const Stall s{static_cast<double>(from), static_cast<double>(to)};
  if (s.to - s.from > longest_us) stalls_.push_back(s);
}

bool StallWatch::StillNear(Stall* s, double t, std::optional<double> error_m) const {
  if (s->recovered || t < s->from - kFlagBeforeUs || t > LatestRecovery(s->from, s->to)) return false;
  if (s->threshold_m < 0.0) s->threshold_m = std::max(kNormalFloorM, kNormalFactor * NormalBefore(s->from));
  if (t <= s->to + kSettleUs) return true;
  if (!error_m || *error_m > s->threshold_m) {
    s->normal_since = 0.0;
    return true;
  }
  if (s->normal_since == 0.0) s->normal_since = t;
  if (t - s->normal_since < kNormalForUs) return true;
  s->recovered = true;
  return false;
}

double StallWatch::NormalBefore(double from) const {
  double largest = 0.0;
  for (const Tracking& r : recent_) {
    if (r.utime < from - kFlagBeforeUs && r.utime >= from - kFlagBeforeUs - kNormalLookbackUs) {
      largest = std::max(largest, r.error_m);
    }
  }
  return largest;
}

}  // namespace edsp
