#include "group_watch.h"

#include "edsp/node/runtime.h"

namespace edsp::test_support {

GroupWatch::GroupWatch(const std::string& lcm_url, const std::string& channels) : lcm_(lcm_url) {
  if (!lcm_.good()) return;
  // A plain function with a context: GCC 12's UBSan breaks LCM's
  // member-function subscribe (transport/ does the same).
  lcm_.subscribeFunction("EDSP_SETPOINT", &GroupWatch::OnMessage, this);
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

void GroupWatch::Listen() {
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stop_) return;
    }
    lcm_.handleTimeout(20);
  }
}

void GroupWatch::OnMessage(const lcm::ReceiveBuffer* buffer, const std::string& channel, GroupWatch* self) {
  const std::int64_t now = UtimeNow();
  pose_setpoint_t setpoint;
  const bool is_setpoint = channel == "EDSP_SETPOINT" &&
                           setpoint.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) >= 0;
  {
    std::lock_guard<std::mutex> lock(self->mutex_);
    self->last_received_utime_[channel] = now;
    if (is_setpoint) {
      self->setpoint_ = setpoint;
      self->have_setpoint_ = true;
    }
  }
  self->changed_.notify_all();
}

bool GroupWatch::WaitForSetpoint(const std::function<bool(const pose_setpoint_t&)>& reached,
                                 std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return have_setpoint_ && reached(setpoint_); });
}

bool GroupWatch::WaitForMessage(const std::string& channel, std::int64_t after_utime,
                                std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] {
    const auto it = last_received_utime_.find(channel);
    return it != last_received_utime_.end() && it->second >= after_utime;
  });
}

}  // namespace edsp::test_support
