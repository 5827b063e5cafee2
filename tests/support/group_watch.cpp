#include "group_watch.h"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cmath>

#include "edsp/fault_t.hpp"
#include "edsp/node/runtime.h"
#include "edsp/rig_truth_t.hpp"

namespace edsp::test_support {

GroupWatch::GroupWatch(const std::string& lcm_url, const std::string& channels) : lcm_(lcm_url) {
  if (!lcm_.good()) return;
  // A plain function with a context: GCC 12's UBSan breaks LCM's
  // member-function subscribe (transport/ does the same).
  lcm_.subscribeFunction("EDSP_SETPOINT", &GroupWatch::OnMessage, this);
  lcm_.subscribeFunction("EDSP_FAULT", &GroupWatch::OnMessage, this);
  if (channels != "EDSP_RIG_TRUTH") lcm_.subscribeFunction("EDSP_RIG_TRUTH", &GroupWatch::OnMessage, this);
  if (!channels.empty()) lcm_.subscribeFunction(channels, &GroupWatch::OnMessage, this);
  listener_ = std::thread([this] { Listen(); });
}

GroupWatch::~GroupWatch() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  if (listener_.joinable()) listener_.join();
}

// Under the nodes' priorities (60-85 in the shipped groups) and above
// every normal thread; without the privilege it stays a normal thread.
constexpr int kListenerPriority = 20;

void GroupWatch::Listen() {
  sched_param param{};
  param.sched_priority = kListenerPriority;
  (void)pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    if (lcm_.handleTimeout(20) < 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

namespace {

// An edsp message's seq: after the 8-byte fingerprint and the utime, big-endian.
std::int64_t SeqOf(const lcm::ReceiveBuffer* buffer) {
  if (buffer->data_size < 24) return -1;
  const auto* bytes = static_cast<const std::uint8_t*>(buffer->data) + 16;
  std::uint64_t seq = 0;
  for (int k = 0; k < 8; ++k) seq = (seq << 8) | bytes[k];
  return static_cast<std::int64_t>(seq);
}

bool DecodeFault(const std::string& channel, const lcm::ReceiveBuffer* buffer, fault_t* fault) {
  return channel == "EDSP_FAULT" && fault->decode(buffer->data, 0, static_cast<int>(buffer->data_size)) >= 0;
}

bool AsksForReArm(const fault_t& fault) {
  return fault.node == "actuator_bridge" && fault.severity == fault_t::SEVERITY_ERROR &&
         (fault.reason.find("until re-armed") != std::string::npos ||
          fault.reason.find("re-arm required") != std::string::npos);
}

}  // namespace

void GroupWatch::OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel, GroupWatch* self) {
  const std::int64_t now = UtimeNow();
  const std::int64_t seq = SeqOf(buffer);
  pose_setpoint_t setpoint;
  const bool is_setpoint =
      channel == "EDSP_SETPOINT" && setpoint.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) >= 0;
  rig_truth_t truth;
  const bool is_truth =
      channel == "EDSP_RIG_TRUTH" && truth.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) >= 0;
  {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->last_received_utime_[channel] = now;
    const auto last = self->last_seq_.find(channel);
    if (last != self->last_seq_.end() && seq >= 0 && seq < last->second) ++self->restarts_[channel];
    self->last_seq_[channel] = seq;
    if (is_setpoint) {
      self->setpoint_ = setpoint;
      self->setpoint_lag_us_ = now - setpoint.utime;
      self->have_setpoint_ = true;
    }
    if (is_truth) self->TrackRest(truth.pose, now);
    fault_t fault;
    if (DecodeFault(channel, buffer, &fault)) {
      if (AsksForReArm(fault)) self->last_rearm_request_utime_ = now;
      self->faults_.push_back(fault);
    }
  }
  self->changed_.notify_all();
}

void GroupWatch::TrackRest(const double (&pose)[6], std::int64_t now) {
  constexpr double kStill = 1e-6;  // m, as the fault tests' AtRestFrom reads the log
  const double moved = std::hypot(pose[0] - rest_anchor_[0], pose[1] - rest_anchor_[1], pose[2] - rest_anchor_[2]);
  if (last_truth_utime_ == 0 || moved > kStill) {
    rest_anchor_ = {pose[0], pose[1], pose[2]};
    rest_anchor_utime_ = now;
  }
  last_truth_utime_ = now;
}

bool GroupWatch::WaitForRest(std::int64_t after_utime, std::chrono::milliseconds still_for,
                             std::chrono::milliseconds timeout) {
  const std::int64_t still_us = std::chrono::duration_cast<std::chrono::microseconds>(still_for).count();
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout,
                           [&] { return last_truth_utime_ - std::max(rest_anchor_utime_, after_utime) >= still_us; });
}

bool GroupWatch::WaitForSetpoint(const std::function<bool(const pose_setpoint_t&)>& reached,
                                 std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return have_setpoint_ && reached(setpoint_); });
}

std::int64_t GroupWatch::SetpointLagUs() {
  std::lock_guard<std::mutex> lock(mutex_);
  return setpoint_lag_us_;
}

int GroupWatch::Restarts(const std::string& channel) {
  std::lock_guard<std::mutex> lock(mutex_);
  return restarts_[channel];
}

bool GroupWatch::WaitForRestart(const std::string& channel, int seen, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return restarts_[channel] > seen; });
}

std::int64_t GroupWatch::LastReArmRequestUtime() {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_rearm_request_utime_;
}

bool GroupWatch::WaitForFault(const std::string& node, const std::string& text, std::int64_t after_utime,
                              std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] {
    for (const fault_t& f : faults_) {
      if (f.node == node && f.utime >= after_utime && f.reason.find(text) != std::string::npos) return true;
    }
    return false;
  });
}

bool GroupWatch::WaitForMessage(const std::string& channel, std::int64_t after_utime,
                                std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] {
    const auto it = last_received_utime_.find(channel);
    return it != last_received_utime_.end() && it->second >= after_utime;
  });
}

int ReArmWhileLatched(GroupWatch* watch, const std::function<void()>& arm) {
  int arms = 0;
  std::int64_t armed_utime = UtimeNow();
  while (watch->WaitForMessage("EDSP_SETPOINT", UtimeNow(), std::chrono::seconds(2))) {
    if (watch->LastReArmRequestUtime() > armed_utime + 300000) {
      arm();
      armed_utime = UtimeNow();
      ++arms;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return arms;
}

}  // namespace edsp::test_support
