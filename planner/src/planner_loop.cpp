#include "edsp/planner/planner_loop.h"

#include <cmath>

#include "edsp/channels.h"
#include "edsp/node/fault.h"
#include "edsp/node/node_loop.h"
#include "edsp/node/scheduling.h"

namespace edsp {

PlannerLoop::PlannerLoop(Bus& bus, MotionService& service, PlannerLoopOptions options)
    : bus_(bus),
      service_(service),
      options_(options),
      setpoints_(bus.Advertise<pose_setpoint_t>(channel::kSetpoint)),
      replies_(bus.Advertise<motion_reply_t>(channel::kMotionReply)),
      motion_status_(bus.Advertise<motion_status_t>(channel::kMotionStatus)),
      reporting_(bus, "planner") {
  reporting_.WatchInput(bus, channel::kMotionRequest);
  bus.Subscribe<motion_request_t>(channel::kMotionRequest,
                                  [this](const motion_request_t& request) { OnRequest(request); });
  bus.Subscribe<leg_state_t>(channel::kLegState,
                             [this](const leg_state_t& legs) { service_.OnLegState(legs, UtimeNow()); });
  bus.Subscribe<platform_state_t>(
      channel::kPlatformState, [this](const platform_state_t& state) { service_.OnPlatformState(state, UtimeNow()); });
  bus.Subscribe<pose_setpoint_t>(channel::kCueSetpoint,
                                 [this](const pose_setpoint_t& cue) { service_.OnCueSetpoint(cue, UtimeNow()); });
}

PlannerLoop::~PlannerLoop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void PlannerLoop::OnRequest(const motion_request_t& request) {
  reporting_.status().CountIn();
  const std::int64_t came_utime = UtimeNow();
  if (MotionService::IsQuick(request)) {
    const motion_reply_t reply = service_.Handle(request, came_utime);
    const std::lock_guard<std::mutex> lock(mutex_);
    replies_out_.push_back(reply);
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    to_plan_.emplace_back(request, came_utime);
    if (!worker_.joinable()) worker_ = std::thread([this] { PlanRequests(); });
  }
  wake_.notify_one();
}

void PlannerLoop::PlanRequests() {
  LeaveRealTime();  // the loop's cycles preempt a check, however long it takes
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return quit_ || !to_plan_.empty(); });
    if (quit_) return;
    const auto [request, came_utime] = to_plan_.front();
    to_plan_.pop_front();
    lock.unlock();
    const motion_reply_t reply = service_.Handle(request, came_utime);
    lock.lock();
    replies_out_.push_back(reply);
  }
}

void PlannerLoop::PublishReplies() {
  std::deque<motion_reply_t> out;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    out.swap(replies_out_);
  }
  for (const motion_reply_t& reply : out) {
    if (!reply.accepted) reporting_.status().CountRejected();
    replies_.Publish(reply);
  }
}

bool PlannerLoop::RunCycle(std::int64_t now_utime, std::int64_t deadline_misses) {
  const auto began = std::chrono::steady_clock::now();
  if (setpoints_.Publish(service_.Step(now_utime))) reporting_.status().CountOut();
  PublishReplies();
  if (service_.TakeChange() || now_utime >= next_motion_status_utime_) {
    motion_status_t status = service_.Status(now_utime);
    status.seq = ++motion_status_seq_;
    motion_status_.Publish(status);
    next_motion_status_utime_ = now_utime + std::llround(1e6 / options_.status_rate_hz);
  }
  bool go_on = true;
  if (!service_.busy() && service_.ended_utime() != 0) {
    reporting_.status().SetState(node_status_t::STATE_HOLDING);
    go_on = options_.exit_after_hold_s < 0.0 ||
            now_utime < service_.ended_utime() + std::llround(options_.exit_after_hold_s * 1e6);
  } else {
    reporting_.status().SetState(node_status_t::STATE_RUNNING);
  }
  if (std::optional<MotionService::CueFault> fault = service_.TakeCueFault()) {
    reporting_.Fault(MakeFault("planner", channel::kCueSetpoint, fault->code, fault_t::SEVERITY_ERROR,
                               std::move(fault->reason), now_utime));
  }
  reporting_.EndCycle(began, now_utime, deadline_misses);
  return go_on;
}

void PlannerLoop::Run(CycleClock& clock, const std::function<bool()>& stop) {
  RunOnClock(bus_, clock, stop, [this](std::int64_t now, std::int64_t missed) { return RunCycle(now, missed); });
}

}  // namespace edsp
