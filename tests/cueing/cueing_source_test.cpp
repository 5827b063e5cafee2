// edsp-cueing's cycle without a bus: the host's command word through
// engage, washout, disengage, freeze and e-stop, the planner's refusals and
// ends, and a lost input; each judged by the cue it publishes (continuous,
// home where it should be, no leg accelerating beyond the platform's limit)
// and the requests it sends (one per step, none twice).
#include "edsp/cueing/cueing_source.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

constexpr double kPeriod_s = 1e-3;

// A host sending one packet a cycle, and the source it drives.
class VehicleHost : public testing::Test {
 protected:
  VehicleHost()
      : model_(LoadConfigFile(SourceDir() + "/config/huang2021.toml")),
        config_(LoadCueingConfig(SourceDir() + "/config/cueing.toml")),
        source_(config_, model_.home_pose().ToVector()) {}

  // One cycle: a packet (unless silent), then the source's step.
  CueingStep Cycle(CueCommand command, double fx = 0.0, bool silent = false) {
    if (!silent) {
      VehiclePacket p;
      p.command = command;
      p.sequence = ++sequence_;
      p.time_s = now_s_;
      p.specific_force_m_s2.x() = fx;
      EXPECT_FALSE(source_.OnPacket(p, now_s_).has_value());
    }
    CueingStep step = source_.Step(now_s_);
    now_s_ += kPeriod_s;
    if (step.cue) cues_.push_back(*step.cue);
    if (step.request) requests_.push_back(*step.request);
    return step;
  }
  // Engaged, the planner following: the cycle the washout starts.
  void Engage(double fx = 0.0) {
    CueingStep first = Cycle(CueCommand::kEngage, fx);
    ASSERT_EQ(first.request, CueRequest::kEngage);
    ASSERT_TRUE(first.cue.has_value()) << "a cue goes out with the request: the planner may follow at once";
    for (int cycle = 0; cycle < 50; ++cycle) {
      const CueingStep s = Cycle(CueCommand::kEngage, fx);
      ASSERT_TRUE(s.cue.has_value()) << "the cue waits at neutral while the planner moves there";
      ASSERT_EQ(s.cue->pose, source_.neutral_pose());
      ASSERT_FALSE(s.request.has_value()) << "one engage request";
    }
    source_.OnReply(CueRequest::kEngage, true, "");
    source_.OnPlannerFollows(true, "");
    Cycle(CueCommand::kEngage, fx);
    ASSERT_EQ(source_.phase(), CueingPhase::kEngaged);
  }
  // The largest leg acceleration along the cues published (from the legs' own lengths).
  double PeakLegAcceleration(std::size_t from = 0) const {
    double peak = 0.0;
    for (std::size_t k = from + 2; k < cues_.size(); ++k) {
      const Vector6 a = model_.LegLengths(Pose::FromVector(cues_[k].pose)),
                    b = model_.LegLengths(Pose::FromVector(cues_[k - 1].pose)),
                    c = model_.LegLengths(Pose::FromVector(cues_[k - 2].pose));
      peak = std::max(peak, ((a - 2.0 * b + c) / (kPeriod_s * kPeriod_s)).cwiseAbs().maxCoeff());
    }
    return peak;
  }
  double FromNeutral(const CueSetpoint& cue) const { return (cue.pose - source_.neutral_pose()).norm(); }

  PlatformModel model_;
  CueingConfig config_;
  CueingSource source_;
  double now_s_ = 100.0;
  std::uint32_t sequence_ = 0;
  std::vector<CueSetpoint> cues_;
  std::vector<CueRequest> requests_;
};

TEST_F(VehicleHost, EngagingWaitsAtNeutralThenFadesTheBrakeInWithoutAStep) {
  Engage(-4.9);
  for (int cycle = 0; cycle < 3000; ++cycle) Cycle(CueCommand::kEngage, -4.9);
  EXPECT_EQ(requests_.size(), 1u);
  const std::size_t engaged = 52;  // the first cue of the washout: after the request's, 50 waiting, the switch's
  EXPECT_LT(FromNeutral(cues_[engaged]), 1e-9) << "the washout starts from rest at neutral";
  EXPECT_LT(cues_[engaged].acceleration.norm(), 1e-3);
  EXPECT_GT(cues_.back().pose(4), 0.0) << "a brake tilts the rider nose down (pitch > 0, docs/cueing.md)";
  EXPECT_LT(cues_[engaged + 500].pose(0), source_.neutral_pose()(0)) << "its onset surges the head back";
  EXPECT_LE(PeakLegAcceleration(), model_.config().motion.leg_accel_max_m_s2);
}

TEST_F(VehicleHost, DisengageFadesOutWashesHomeThenAsksOnce) {
  Engage(-4.9);
  for (int cycle = 0; cycle < 2000; ++cycle) Cycle(CueCommand::kEngage, -4.9);
  ASSERT_GT(FromNeutral(cues_.back()), 1e-3);
  const std::size_t from = cues_.size();
  int cycles = 0;
  while (requests_.size() == 1 && cycles < 40'000) {
    Cycle(CueCommand::kDisengage, -4.9);
    ++cycles;
  }
  ASSERT_EQ(requests_.size(), 2u) << "never asked to disengage";
  EXPECT_EQ(requests_.back(), CueRequest::kDisengage);
  EXPECT_LT(cycles * kPeriod_s, kWashoutTimeout_s) << "home before the timeout";
  EXPECT_LT(FromNeutral(cues_.back()), 3e-4) << "the platform at neutral when the planner is asked";
  EXPECT_LE(PeakLegAcceleration(from - 2), model_.config().motion.leg_accel_max_m_s2);
  for (int cycle = 0; cycle < 10; ++cycle) Cycle(CueCommand::kDisengage);
  EXPECT_EQ(requests_.size(), 2u) << "asked once";
  source_.OnReply(CueRequest::kDisengage, true, "");
  source_.OnPlannerFollows(false, "");
  EXPECT_FALSE(Cycle(CueCommand::kDisengage).cue.has_value());
  EXPECT_EQ(source_.phase(), CueingPhase::kDisengaged);
}

TEST_F(VehicleHost, ALostInputWashesTheCueHomeEngagedWithinTheLegsLimit) {
  Engage(-4.9);
  for (int cycle = 0; cycle < 2500; ++cycle) Cycle(CueCommand::kEngage, -4.9);
  const std::size_t from = cues_.size();
  for (int cycle = 0; cycle < 30'000; ++cycle) Cycle(CueCommand::kEngage, 0.0, /*silent=*/true);
  EXPECT_EQ(source_.phase(), CueingPhase::kEngaged);
  EXPECT_LT(FromNeutral(cues_.back()), 1e-4) << "washed out to neutral";
  EXPECT_LE(PeakLegAcceleration(from - 2), model_.config().motion.leg_accel_max_m_s2);
  EXPECT_EQ(requests_.size(), 1u);
}

TEST_F(VehicleHost, AFreezeBrakesTheCueToRestAndHoldsIt) {
  Engage(-4.9);
  for (int cycle = 0; cycle < 1500; ++cycle) Cycle(CueCommand::kEngage, -4.9);
  const double speed = cues_.back().velocity.head<3>().norm();
  ASSERT_GT(speed, 1e-3);
  const std::size_t from = cues_.size();
  for (int cycle = 0; cycle < 2000; ++cycle) Cycle(CueCommand::kFreeze, -4.9);
  EXPECT_EQ(source_.phase(), CueingPhase::kFrozen);
  double previous = speed;
  std::size_t translation_stopped = 0, stopped = 0;  // the first cue at rest in translation, then in all
  for (std::size_t k = from; k < cues_.size(); ++k) {
    const double v = cues_[k].velocity.head<3>().norm();
    ASSERT_LE(v, previous + 1e-15) << "slows at every cycle";
    ASSERT_LE(cues_[k].acceleration.head<3>().norm(), kFreezeBrake_m_s2 * (1 + 1e-9));
    ASSERT_LE(cues_[k].acceleration.tail<3>().norm(), kFreezeBrake_rad_s2 * (1 + 1e-9));
    if (v == 0.0 && translation_stopped == 0) translation_stopped = k;
    if (cues_[k].velocity.isZero(0.0) && stopped == 0) stopped = k;
    previous = v;
  }
  ASSERT_GT(translation_stopped, 0u);
  ASSERT_GT(stopped, 0u);
  EXPECT_NEAR(static_cast<double>(translation_stopped - from) * kPeriod_s, speed / kFreezeBrake_m_s2, 2e-3)
      << "at the brake's deceleration";
  EXPECT_EQ(cues_.back().pose, cues_[stopped].pose) << "held";
  Cycle(CueCommand::kDisengage);
  EXPECT_EQ(requests_.back(), CueRequest::kDisengage);
}

TEST_F(VehicleHost, AnEStopAsksForAStopOnceAndOnlyDisengageThenEngageRestarts) {
  Engage();
  for (int cycle = 0; cycle < 100; ++cycle) Cycle(CueCommand::kEngage);
  for (int cycle = 0; cycle < 100; ++cycle) EXPECT_FALSE(Cycle(CueCommand::kEStop).cue.has_value());
  ASSERT_EQ(requests_.size(), 2u);
  EXPECT_EQ(requests_.back(), CueRequest::kStop);
  EXPECT_EQ(source_.why_stopped(), "e-stop from the host");
  source_.OnReply(CueRequest::kStop, true, "");
  source_.OnPlannerFollows(false, "stop");
  for (int cycle = 0; cycle < 100; ++cycle) Cycle(CueCommand::kEngage);
  EXPECT_EQ(requests_.size(), 2u) << "engage alone does not restart after an e-stop";
  Cycle(CueCommand::kDisengage);
  EXPECT_EQ(source_.phase(), CueingPhase::kDisengaged);
  Cycle(CueCommand::kEngage);
  EXPECT_EQ(requests_.back(), CueRequest::kEngage);
}

TEST_F(VehicleHost, ARefusedEngageAndAPlannerThatEndsTheCueingStopItWithTheReason) {
  Cycle(CueCommand::kEngage);
  source_.OnReply(CueRequest::kEngage, false, "move is in progress");
  Cycle(CueCommand::kEngage);
  EXPECT_EQ(source_.phase(), CueingPhase::kStopped);
  EXPECT_EQ(source_.why_stopped(), "engage refused by the planner: move is in progress");
  Cycle(CueCommand::kDisengage);
  Engage();
  source_.OnPlannerFollows(false, "cueing from edsp-cueing ended: no EDSP_CUE_SETPOINT for 21 ms");
  EXPECT_FALSE(Cycle(CueCommand::kEngage).cue.has_value());
  EXPECT_EQ(source_.why_stopped(),
            "the planner ended the cueing: cueing from edsp-cueing ended: no EDSP_CUE_SETPOINT for 21 ms");
}

TEST_F(VehicleHost, NothingIsAskedBeforeAnEngageWordArrives) {
  for (int cycle = 0; cycle < 100; ++cycle) Cycle(CueCommand::kDisengage);
  for (int cycle = 0; cycle < 100; ++cycle) Cycle(CueCommand::kEngage, 0.0, /*silent=*/true);
  EXPECT_TRUE(requests_.empty());
  EXPECT_TRUE(cues_.empty());
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

// A cycle the scheduler delayed: the source catches up one washout step per
// period, so its cue equals that of a source that ran every cycle.
TEST(CueingSourceCatchUp, ADelayedCycleGivesTheCueOfEveryCycleRun) {
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const Vector6 neutral = PlatformModel(LoadConfigFile(SourceDir() + "/config/huang2021.toml")).home_pose().ToVector();
  CueingSource every(config, neutral), delayed(config, neutral);
  for (CueingSource* s : {&every, &delayed}) {
    s->Step(0.0);
    s->OnPlannerFollows(true, "");
  }
  VehiclePacket p;
  p.specific_force_m_s2.x() = -4.9;
  CueSetpoint last_every, last_delayed;
  for (int cycle = 1; cycle <= 2500; ++cycle) {
    const double t = cycle * 1e-3;
    p.sequence = static_cast<std::uint32_t>(cycle);
    p.time_s = t;
    for (CueingSource* s : {&every, &delayed}) ASSERT_FALSE(s->OnPacket(p, t).has_value());
    if (auto c = every.Step(t).cue) last_every = *c;
    // Engaged together, faded in together (the input fades in over 1 s); then
    // the delayed one misses three cycles in five.
    if (cycle > 1100 && cycle % 5 != 0 && cycle % 5 != 1) continue;
    if (auto c = delayed.Step(t).cue) last_delayed = *c;
    // Past the input's fade-in (a constant brake): the catch-up steps see what every cycle saw.
    if (cycle > 1200 && cycle % 5 == 0) {
      ASSERT_LT((last_delayed.pose - last_every.pose).cwiseAbs().maxCoeff(), 1e-12) << "cycle " << cycle;
    }
  }
  EXPECT_GT((last_every.pose - neutral).norm(), 1e-3) << "the brake moved the cue";
}

// Leaving a freeze by engage: the washout restarts from rest where a source
// engaged at that instant starts (run beside it, on the same packets), and
// the cue returns from where the freeze held it to that one's along a
// raised cosine: no step in pose or velocity, no harder than the freeze's
// brake, and after the return the two are one cue.
TEST(CueingSourceFreeze, EngageAfterAFreezeReturnsIntoTheWashoutOfASourceEngagedThen) {
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const Vector6 neutral = PlatformModel(LoadConfigFile(SourceDir() + "/config/huang2021.toml")).home_pose().ToVector();
  CueingSource resumed(config, neutral), fresh(config, neutral);
  const auto send = [](CueingSource& source, int cycle, CueCommand command) {
    VehiclePacket p;
    p.command = command;
    p.sequence = static_cast<std::uint32_t>(cycle + 1);
    p.time_s = cycle * 1e-3;
    p.specific_force_m_s2.x() = -4.9;  // braking throughout
    return source.OnPacket(p, cycle * 1e-3);
  };
  constexpr int kFreezeAt = 1500, kEngageAt = 3500;
  std::vector<CueSetpoint> a, b;  // resumed's and fresh's cues, from the engage word on
  int resumed_at = -1;
  for (int cycle = 0; cycle < kEngageAt + 8000; ++cycle) {
    const double t = cycle * 1e-3;
    ASSERT_FALSE(
        send(resumed, cycle, cycle < kFreezeAt || cycle >= kEngageAt ? CueCommand::kEngage : CueCommand::kFreeze));
    const CueingStep step = resumed.Step(t);
    if (cycle == 0) {
      ASSERT_EQ(step.request, CueRequest::kEngage);
      resumed.OnReply(CueRequest::kEngage, true, "");
      resumed.OnPlannerFollows(true, "");
    }
    // The other source hears the vehicle from the freeze on (its input faded
    // in by then), disengaged until a cycle before the engage word: its
    // request then, the planner following it at once.
    if (cycle >= kFreezeAt) {
      ASSERT_FALSE(send(fresh, cycle, cycle < kEngageAt - 1 ? CueCommand::kDisengage : CueCommand::kEngage));
      const CueingStep other = fresh.Step(t);
      if (other.request) {
        ASSERT_EQ(*other.request, CueRequest::kEngage);
        fresh.OnReply(CueRequest::kEngage, true, "");
        fresh.OnPlannerFollows(true, "");
      }
      if (cycle >= kEngageAt) {
        ASSERT_TRUE(step.cue && other.cue) << "cycle " << cycle;
        a.push_back(*step.cue);
        b.push_back(*other.cue);
      }
    }
    if (cycle == kEngageAt - 1) {
      ASSERT_EQ(resumed.phase(), CueingPhase::kFrozen);
      ASSERT_TRUE(step.cue->velocity.isZero(0.0)) << "braked to rest by then";
    }
    if (resumed_at < 0 && cycle >= kEngageAt && resumed.phase() == CueingPhase::kEngaged) resumed_at = cycle;
  }
  ASSERT_EQ(resumed_at, kEngageAt) << "engage at rest leaves the freeze at once";
  const Vector6 held = a.front().pose;
  const Vector6 offset = held - neutral;
  ASSERT_GT(offset.head<3>().norm(), 1e-3) << "the freeze held the cue away from neutral";
  // The longest return the brake allows (a raised cosine of amplitude A over T peaks at π²A/(2T²)).
  const double longest_s =
      std::max({config.input.fade_s, kPi * std::sqrt(offset.head<3>().norm() / (2.0 * kFreezeBrake_m_s2)),
                kPi * std::sqrt(offset.tail<3>().norm() / (2.0 * kFreezeBrake_rad_s2))});
  std::size_t joined = 0;  // the first cue equal to the fresh source's
  for (std::size_t k = 1; k < a.size(); ++k) {
    ASSERT_LT((a[k].velocity - a[k - 1].velocity).norm(), 5e-3) << "no step in velocity at cue " << k;
    if (k >= 2) {
      // The return alone: the difference from the washout engaged then.
      const Vector6 d2 =
          ((a[k].pose - b[k].pose) - 2.0 * (a[k - 1].pose - b[k - 1].pose) + (a[k - 2].pose - b[k - 2].pose)) / 1e-6;
      ASSERT_LE(d2.head<3>().norm(), kFreezeBrake_m_s2 * (1 + 1e-3) + 1e-6) << "cue " << k;
      ASSERT_LE(d2.tail<3>().norm(), kFreezeBrake_rad_s2 * (1 + 1e-3) + 1e-6) << "cue " << k;
    }
    if (joined == 0 && (a[k].pose - b[k].pose).norm() < 1e-9) joined = k;
  }
  EXPECT_LT((a[1].pose - b[1].pose - offset).norm(), 1e-3 * offset.norm()) << "the return starts from the hold";
  EXPECT_LT(a[1].velocity.norm(), 1e-3) << "and from rest";
  ASSERT_GT(joined, 0u) << "the cue never joined the washout";
  EXPECT_LE(static_cast<double>(joined) * 1e-3, longest_s + 2e-3);
  for (std::size_t k = joined; k < a.size(); ++k) {
    ASSERT_LT((a[k].pose - b[k].pose).norm(), 1e-9) << "one cue from the return's end on, cue " << k;
  }
  EXPECT_GT((a.back().pose - neutral).norm(), 1e-3) << "still braking: the washout moves the cue";
}

// A host whose scheduler wakes the cycle late by up to most of a period,
// and now and then by several (the clock then skips the ticks it missed):
// each cue is the one a source run on time gives for the instant it is
// stamped with, through a brake and a freeze that brakes it to rest.
TEST(CueingSourceClock, ACueIsOfTheTimeItIsStampedWithHoweverLateItsCycleWoke) {
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  const Vector6 neutral = PlatformModel(LoadConfigFile(SourceDir() + "/config/huang2021.toml")).home_pose().ToVector();
  CueingSource on_time(config, neutral), woken_late(config, neutral);
  for (CueingSource* s : {&on_time, &woken_late}) {
    s->Step(0.0);
    s->OnPlannerFollows(true, "");
  }
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> lateness(0.0, 0.95);
  std::vector<Vector6> on_time_poses{neutral};
  VehiclePacket p;
  p.specific_force_m_s2.x() = -4.9;
  double last_wake = 0.0;
  std::vector<std::pair<long, Vector6>> late_cues;  // the late source's: the tick each is stamped at
  int ahead = 0, skipped = 0;
  for (int cycle = 1; cycle <= 4000; ++cycle) {
    const double t = cycle * kPeriod_s;
    p.command = cycle < 3000 ? CueCommand::kEngage : CueCommand::kFreeze;
    p.sequence = static_cast<std::uint32_t>(cycle);
    p.time_s = t;
    for (CueingSource* s : {&on_time, &woken_late}) ASSERT_FALSE(s->OnPacket(p, t).has_value());
    const CueingStep step = on_time.Step(t);
    ASSERT_TRUE(step.cue.has_value());
    ASSERT_NEAR(step.time_s, t, 1e-9);
    on_time_poses.push_back(step.cue->pose);
    if (t < last_wake) continue;  // the late cycle before overran this tick
    // On time while the input and the engage fade in (each from the tick the
    // source first saw the packet) and around the freeze word: a packet seen
    // a tick later is another input, not what is compared.
    const bool jitter = cycle > 1100 && std::abs(cycle - 3000) > 5;
    const double late_periods = !jitter ? 0.0 : cycle % 97 == 0 ? 3.4 : lateness(rng);
    last_wake = t + late_periods * kPeriod_s;
    const CueingStep late = woken_late.Step(last_wake);
    if (!late.cue) {
      ++skipped;
      continue;
    }
    ASSERT_LE(std::abs(late.time_s - last_wake), 0.5 * kPeriod_s + 1e-9) << "cycle " << cycle;
    const long tick = std::lround(late.time_s / kPeriod_s);
    ahead += tick > cycle;
    late_cues.emplace_back(tick, late.cue->pose);
  }
  for (const auto& [tick, pose] : late_cues) {
    if (tick >= static_cast<long>(on_time_poses.size())) continue;
    ASSERT_LT((pose - on_time_poses[static_cast<std::size_t>(tick)]).cwiseAbs().maxCoeff(), 1e-9)
        << "the cue stamped at tick " << tick;
  }
  EXPECT_GT((on_time_poses[2999] - neutral).norm(), 1e-3) << "the brake moved the cue";
  EXPECT_GT(late_cues.size(), 2000u);
  EXPECT_GT(ahead, 100) << "cycles woken over half a period late: their cue is of the next tick";
  EXPECT_GT(skipped, 100) << "cycles woken early after such a one";
  std::printf("%zu cues compared, %d of the tick after their cycle's, %d cycles gave none\n", late_cues.size(), ahead,
              skipped);
}

// A source engaged on time and braking at a constant input until `until`
// periods, packets from a host at 1 kHz.
class BrakingSource {
 public:
  BrakingSource()
      : source_(LoadCueingConfig(SourceDir() + "/config/cueing.toml"),
                PlatformModel(LoadConfigFile(SourceDir() + "/config/huang2021.toml")).home_pose().ToVector()) {
    source_.Step(0.0);
    source_.OnPlannerFollows(true, "");
  }
  void Packet(int cycle, CueCommand command = CueCommand::kEngage) {
    VehiclePacket p;
    p.command = command;
    p.specific_force_m_s2.x() = -4.9;
    p.sequence = static_cast<std::uint32_t>(cycle);
    p.time_s = cycle * kPeriod_s;
    ASSERT_FALSE(source_.OnPacket(p, p.time_s).has_value());
  }
  CueingStep RunTo(int cycles) {
    CueingStep last;
    for (int cycle = 1; cycle <= cycles; ++cycle) {
      Packet(cycle);
      last = source_.Step(cycle * kPeriod_s);
    }
    return last;
  }
  CueingSource& source() { return source_; }

 private:
  CueingSource source_;
};

// A stall longer than the catch-up: twenty periods are run, the rest
// skipped, and the cue is stamped with the wall time it ran at.
TEST(CueingSourceClock, AStallLongerThanTheCatchUpRunsTwentyPeriodsAndIsStampedWhenItRan) {
  BrakingSource stalled, reference;
  stalled.RunTo(2000);
  reference.RunTo(2000);
  const CueingStep late = stalled.source().Step(2050.3 * kPeriod_s);
  const CueingStep twenty = reference.source().Step(2020 * kPeriod_s);
  ASSERT_TRUE(late.cue && twenty.cue);
  EXPECT_NEAR(late.time_s, 2050 * kPeriod_s, 1e-9);
  EXPECT_LT((late.cue->pose - twenty.cue->pose).cwiseAbs().maxCoeff(), 1e-12);
  const CueingStep next = stalled.source().Step(2051.1 * kPeriod_s);
  ASSERT_TRUE(next.cue);
  EXPECT_NEAR(next.time_s, 2051 * kPeriod_s, 1e-9);
}

// An e-stop word that arrives before a cycle with no period due (woken
// early after a late one) is answered in that cycle, not the next.
TEST(CueingSourceClock, AnEStopIsAskedForInACycleWithNoPeriodDue) {
  BrakingSource braking;
  braking.RunTo(1500);
  ASSERT_TRUE(braking.source().Step(1501.6 * kPeriod_s).cue) << "late: the tick after";
  braking.Packet(1502, CueCommand::kEStop);
  const CueingStep early = braking.source().Step(1502.05 * kPeriod_s);
  EXPECT_FALSE(early.cue) << "no period due";
  ASSERT_TRUE(early.request.has_value());
  EXPECT_EQ(*early.request, CueRequest::kStop);
  EXPECT_EQ(braking.source().phase(), CueingPhase::kStopped);
}

// The wall clock stepped back (NTP): the source's clock follows it and
// steps on, one period a cycle, instead of going quiet until the wall
// clock has caught up with it.
TEST(CueingSourceClock, AWallClockSteppedBackTakesTheSourcesClockWithIt) {
  BrakingSource braking;
  braking.RunTo(1500);
  for (int k = 0; k < 5; ++k) {
    const double wall = (1500 - 200 + k) * kPeriod_s;
    braking.Packet(1501 + k);
    const CueingStep step = braking.source().Step(wall);
    ASSERT_TRUE(step.cue) << "cycle " << k << " after the step back";
    EXPECT_NEAR(step.time_s, wall, 0.5 * kPeriod_s + 1e-9);
  }
}

}  // namespace
}  // namespace edsp
