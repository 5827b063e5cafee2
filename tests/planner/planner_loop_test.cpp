// The planner on a bus (memq://, in process): what edsp-planner publishes
// for the clock it is given: each cycle the trajectory's pose at that time,
// the status running then holding, and the end of the hold it was told.
#include "edsp/planner/planner_loop.h"

#include <pthread.h>
#include <sched.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <thread>
#include <vector>

#include "counting_clock.h"  // tests/support
#include "edsp/kinematics/config.h"
#include "edsp/node/fault.h"
#include "edsp/planner/motion_library.h"
#include "memq_bus.h"         // tests/support
#include "motion_requests.h"  // tests/support

namespace edsp {
namespace {

constexpr std::int64_t kSession = 4;
constexpr std::int64_t kT0 = 1'700'000'000'000'000;  // the motion's time zero, µs

// Up 10 mm in 0.5 s, then held: the trajectory the tests play.
std::unique_ptr<TrajectorySequence> Rise(const PlatformModel& model) {
  Vector6 top = model.home_pose().ToVector();
  top(2) += 0.01;
  auto sequence = std::make_unique<TrajectorySequence>();
  sequence->Append("rise", std::make_unique<QuinticMove>(model.home_pose().ToVector(), top, 0.5));
  return sequence;
}

MotionServiceOptions ServiceOptions() {
  MotionServiceOptions options;
  options.session_id = kSession;
  return options;
}

MotionService& Started(MotionService& service, const PlatformModel& model) {
  service.StartProgram(Rise(model), "rise");
  return service;
}

struct Fixture {
  explicit Fixture(double exit_after_hold_s = -1.0)
      : loop(bus, Started(service, model), PlannerLoopOptions{exit_after_hold_s}) {
    bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [this](const pose_setpoint_t& s) { setpoints.push_back(s); });
    bus.Subscribe<node_status_t>("EDSP_STATUS", [this](const node_status_t& s) { statuses.push_back(s); });
    bus.Subscribe<motion_status_t>("EDSP_MOTION_STATUS",
                                   [this](const motion_status_t& s) { motion_statuses.push_back(s); });
  }
  void HandleAll() {
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }

  Bus bus{test_support::MemqConfig("planner_loop")};
  PlatformModel model{Huang2021Config()};
  MotionService service{model, ServiceOptions()};
  PlannerLoop loop;
  std::vector<pose_setpoint_t> setpoints;
  std::vector<node_status_t> statuses;
  std::vector<motion_status_t> motion_statuses;
};

TEST(PlannerLoop, EachCycleIsTheTrajectorysPoseAtItsTime) {
  Fixture f;
  const auto reference = Rise(f.model);  // the same motion, sampled apart from the loop
  for (std::int64_t ms : {0, 1, 2, 250, 251, 499}) ASSERT_TRUE(f.loop.RunCycle(kT0 + ms * 1000, 0));
  f.HandleAll();
  ASSERT_EQ(f.setpoints.size(), 6u);
  std::int64_t seq = 0;
  for (const pose_setpoint_t& s : f.setpoints) {
    const PoseSample expected = reference->Sample(static_cast<double>(s.utime - kT0) * 1e-6);
    for (int k = 0; k < 6; ++k) {
      EXPECT_DOUBLE_EQ(s.pose[k], expected.pose(k)) << "axis " << k << " at " << s.utime - kT0 << " µs";
      EXPECT_DOUBLE_EQ(s.velocity[k], expected.velocity(k));
    }
    EXPECT_EQ(s.session_id, kSession);
    EXPECT_EQ(s.seq, ++seq);
  }
  // A late cycle (2 → 250 ms) takes the pose of its own time: no drift.
  EXPECT_EQ(f.setpoints[3].utime, kT0 + 250000);
}

TEST(PlannerLoop, RunningThenHoldingTheFinalPoseOnEdspStatus) {
  Fixture f;
  for (std::int64_t ms = 0; ms <= 1600; ++ms) ASSERT_TRUE(f.loop.RunCycle(kT0 + ms * 1000, 0));
  f.HandleAll();
  ASSERT_GE(f.statuses.size(), 2u);
  EXPECT_EQ(f.statuses.front().state, node_status_t::STATE_RUNNING);
  EXPECT_EQ(f.statuses.front().node, "planner");
  EXPECT_EQ(f.statuses.back().state, node_status_t::STATE_HOLDING);
  // The motion ended at 0.5 s: the held pose is its last.
  const Vector6 top = Rise(f.model)->Sample(0.5).pose;
  EXPECT_DOUBLE_EQ(f.setpoints.back().pose[2], top(2));
  EXPECT_EQ(f.setpoints.size(), 1601u) << "one setpoint a cycle, held ones too";
}

// edsp-log counts a seq that does not advance by one as a restart or a
// loss: the motion status counts on like every other stream.
TEST(PlannerLoop, MotionStatusSeqAdvancesByOneAMessage) {
  Fixture f;
  for (std::int64_t ms = 0; ms <= 1000; ++ms) ASSERT_TRUE(f.loop.RunCycle(kT0 + ms * 1000, 0));
  f.HandleAll();
  ASSERT_GE(f.motion_statuses.size(), 40u) << "50 Hz and on every change, over 1 s";
  std::int64_t seq = 0;
  for (const motion_status_t& s : f.motion_statuses) EXPECT_EQ(s.seq, ++seq);
}

TEST(PlannerLoop, ItStopsOnceTheFinalPoseIsHeldAsLongAsItWasTold) {
  Fixture f(0.25);
  std::int64_t ms = 0;
  while (f.loop.RunCycle(kT0 + ms * 1000, 0) && ms < 10000) ++ms;
  EXPECT_EQ(ms, 750) << "0.5 s of motion, then 0.25 s held";
  Fixture forever;
  for (ms = 0; ms <= 5000; ++ms) ASSERT_TRUE(forever.loop.RunCycle(kT0 + ms * 1000, 0)) << "without a limit it holds";
}

TEST(PlannerLoop, RunPublishesOneSetpointPerTickOfItsClockUntilStopped) {
  Fixture f;
  test_support::CountingClock clock(40, 3);
  f.loop.Run(clock, [&] { return clock.done(); });
  f.HandleAll();
  EXPECT_EQ(f.setpoints.size(), 40u);
  ASSERT_FALSE(f.statuses.empty());
  EXPECT_EQ(f.statuses.front().deadline_misses, 3) << "the clock's missed cycles reach EDSP_STATUS";
}

// Moves are planned on the loop's worker while the cycles go on; a halt is
// answered on the loop's own thread; the replies come out in the order the
// requests were acted on.
TEST(PlannerLoop, AMoveIsPlannedBesideTheCyclesAndItsReplyPrecedesALaterHalts) {
  Bus bus{test_support::MemqConfig("planner_loop_requests")};
  const PlatformModel model{Huang2021Config()};
  MotionService service{model, ServiceOptions()};
  PlannerLoop loop(bus, service, PlannerLoopOptions{});
  std::vector<motion_reply_t> replies;
  std::vector<pose_setpoint_t> setpoints;
  bus.Subscribe<motion_reply_t>("EDSP_MOTION_REPLY", [&](const motion_reply_t& r) { replies.push_back(r); });
  bus.Subscribe<pose_setpoint_t>("EDSP_SETPOINT", [&](const pose_setpoint_t& s) { setpoints.push_back(s); });
  leg_state_t legs{};
  for (auto& d : legs.drive_status) d = leg_state_t::DRIVE_ENABLED;
  const auto cycle = [&] {
    legs.utime = UtimeNow();
    bus.Publish("EDSP_LEG_STATE", legs);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
    loop.RunCycle(UtimeNow(), 0);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  test_support::MotionRequests requests(kSession);
  cycle();
  motion_request_t move = requests.Move((Vector6() << 0.05, 0, 0, 0, 0, 0).finished(), UtimeNow(), true);
  bus.Publish("EDSP_MOTION_REQUEST", move);
  for (int k = 0; k < 5000 && replies.empty(); ++k) cycle();  // the machine's pace, not a timing assertion
  ASSERT_EQ(replies.size(), 1u) << "the worker answered";
  EXPECT_TRUE(replies[0].accepted) << replies[0].reason;
  // Halted a tenth of the way, however slowly this machine cycles (a fixed
  // count of cycles would be the whole move on a starved one).
  for (int k = 0; k < 5000 && (setpoints.empty() || setpoints.back().pose[0] <= 0.005); ++k) cycle();
  bus.Publish("EDSP_MOTION_REQUEST", requests.Make(motion_request_t::KIND_HALT, UtimeNow()));
  for (int k = 0; k < 5 && replies.size() < 2; ++k) cycle();
  ASSERT_EQ(replies.size(), 2u) << "a halt is answered at the next cycle";
  EXPECT_EQ(replies[1].kind, motion_request_t::KIND_HALT);
  EXPECT_TRUE(replies[1].accepted);
  EXPECT_GT(setpoints.back().pose[0], 0.0) << "the move ran before the halt";
  EXPECT_LT(setpoints.back().pose[0], 0.05);
}

// The calling thread as a launcher sets a real-time node: SCHED_FIFO on one
// CPU. Undone when the test ends (the binary runs its other tests after).
class RealTimeOnOneCpu {
 public:
  RealTimeOnOneCpu() {
    sched_getaffinity(0, sizeof all_, &all_);
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(sched_getcpu(), &one);
    sched_param param{};
    param.sched_priority = 10;
    ok_ = sched_setaffinity(0, sizeof one, &one) == 0 && pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  }
  ~RealTimeOnOneCpu() {
    sched_param param{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
    sched_setaffinity(0, sizeof all_, &all_);
  }
  bool ok() const { return ok_; }

 private:
  cpu_set_t all_{};
  bool ok_ = false;
};

// A node's worker thread inherits its real-time priority and CPU. Were the
// whole-path check of a program run at it, the cycle (of equal priority, on
// the one CPU) would wait for the check to end: no setpoint for as long as
// it takes. The check is timed by the run itself (request to reply), and no
// gap between two cycles may come near it.
TEST(PlannerLoop, AProgramBeingCheckedNeverHoldsTheCyclesBack) {
  RealTimeOnOneCpu real_time;
  if (!real_time.ok()) GTEST_SKIP() << "SCHED_FIFO refused here (needs root or CAP_SYS_NICE)";
  Bus bus{test_support::MemqConfig("planner_loop_rt")};
  const PlatformModel model{Huang2021Config()};
  MotionService service{model, ServiceOptions()};
  PlannerLoop loop(bus, service, PlannerLoopOptions{});
  std::vector<motion_reply_t> replies;
  bus.Subscribe<motion_reply_t>("EDSP_MOTION_REPLY", [&](const motion_reply_t& r) { replies.push_back(r); });
  leg_state_t legs{};
  for (auto& d : legs.drive_status) d = leg_state_t::DRIVE_ENABLED;
  std::vector<std::int64_t> cycles_utime;
  const auto cycle = [&] {
    legs.utime = UtimeNow();
    bus.Publish("EDSP_LEG_STATE", legs);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
    loop.RunCycle(UtimeNow(), 0);
    cycles_utime.push_back(UtimeNow());
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  test_support::MotionRequests requests(kSession);
  cycle();
  motion_request_t run = requests.Make(motion_request_t::KIND_CHECK, UtimeNow());
  run.kind = motion_request_t::KIND_RUN;
  run.motions = "Lz,Lx,Ly,Rz,Rx,Ry,M1,M2,M3,Lz,Lx,Ly,Rz,Rx,Ry,M1,M2,M3";
  const std::int64_t asked_utime = UtimeNow();
  bus.Publish("EDSP_MOTION_REQUEST", run);
  while (replies.empty() && UtimeNow() - asked_utime < 120'000'000) cycle();
  ASSERT_EQ(replies.size(), 1u) << "the worker answered";
  const std::int64_t answered_utime = cycles_utime.back();
  const std::int64_t check_us = answered_utime - asked_utime;
  ASSERT_GT(check_us, 10'000) << "a check this short tells nothing here: give the test a longer program";
  std::int64_t largest_gap_us = 0;
  for (std::size_t k = 1; k < cycles_utime.size(); ++k) {
    if (cycles_utime[k] < asked_utime) continue;
    largest_gap_us = std::max(largest_gap_us, cycles_utime[k] - cycles_utime[k - 1]);
  }
  EXPECT_LT(largest_gap_us, check_us / 4) << "the check took " << check_us << " us";
}

// Packets on the request channel that are no motion_request_t (noise, a
// request cut short) are refused by the bus and reported once each by the
// planner as undecodable, naming how many; its cycle goes on.
TEST(PlannerLoop, ForeignRequestPacketsAreReportedAsUndecodableAndTheCycleGoesOn) {
  Fixture f;
  std::vector<fault_t> faults;
  f.bus.Subscribe<fault_t>("EDSP_FAULT", [&](const fault_t& fault) { faults.push_back(fault); });
  test_support::MotionRequests requests(kSession);
  const motion_request_t whole = requests.Make(motion_request_t::KIND_HALT, kT0);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(whole.getEncodedSize()));
  whole.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  const std::uint8_t noise[5] = {1, 2, 3, 4, 5};
  f.bus.lcm().Publish("EDSP_MOTION_REQUEST", noise, 5);
  f.bus.lcm().Publish("EDSP_MOTION_REQUEST", bytes.data(), static_cast<std::uint32_t>(bytes.size() / 2));
  f.HandleAll();
  ASSERT_TRUE(f.loop.RunCycle(kT0, 0));
  ASSERT_TRUE(f.loop.RunCycle(kT0 + 1000, 0));  // nothing new: no second report
  f.HandleAll();
  EXPECT_EQ(f.setpoints.size(), 2u);
  std::vector<fault_t> undecodable;
  for (const fault_t& fault : faults) {
    if (fault.code == static_cast<std::int32_t>(FaultCode::kUndecodable)) undecodable.push_back(fault);
  }
  ASSERT_EQ(undecodable.size(), 1u);
  EXPECT_EQ(undecodable[0].node, "planner");
  EXPECT_EQ(undecodable[0].channel, "EDSP_MOTION_REQUEST");
  EXPECT_EQ(undecodable[0].reason.rfind("2 undecodable packets", 0), 0u) << undecodable[0].reason;
}

}  // namespace
}  // namespace edsp
