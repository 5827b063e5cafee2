#include "edsp/cueing/vehicle_input.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "edsp/cueing/raised_cosine.h"

namespace edsp {
const char* VehicleInputStateName(VehicleInputState state) {
  switch (state) {
    case VehicleInputState::kWaiting: return "waiting";
    case VehicleInputState::kLive: return "live";
    case VehicleInputState::kLost: return "lost";
  }
  return "?";
}

VehicleInput::VehicleInput(const VehicleInputParameters& parameters) : parameters_(parameters) {
  for (auto [value, name] : {std::pair{parameters.timeout_s, "timeout_s"}, std::pair{parameters.fade_s, "fade_s"}}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(fmt::format("vehicle input {} = {}: must be finite and > 0", name, value));
    }
  }
}

std::optional<std::string> VehicleInput::Accept(const VehiclePacket& packet, double now_s) {
  // Once lost, the next packet starts a stream of its own: a vehicle model
  // restarted (sequence and time from 0) or one garbled packet must not
  // lock the input out for good.
  if (latest_ && state(now_s) != VehicleInputState::kLost) {
    if (!SequenceIsAhead(packet.sequence, latest_->sequence)) {
      return fmt::format("sequence {} after {}: out of order or repeated", packet.sequence, latest_->sequence);
    }
    // Equal times are a paused (frozen) vehicle; earlier ones are not its.
    if (packet.time_s < latest_->time_s) {
      return fmt::format("time_s {} after {}: the vehicle's time went back", packet.time_s, latest_->time_s);
    }
    missed_packets_ += packet.sequence - latest_->sequence - 1;
  }
  latest_ = packet;
  latest_receive_s_ = now_s;
  return std::nullopt;
}

VehicleInputState VehicleInput::state(double now_s) const {
  if (!latest_) return VehicleInputState::kWaiting;
  return now_s - latest_receive_s_ <= parameters_.timeout_s ? VehicleInputState::kLive : VehicleInputState::kLost;
}

std::optional<CueCommand> VehicleInput::command() const {
  if (!latest_) return std::nullopt;
  return latest_->command;
}

VehicleSample VehicleInput::At(double now_s) {
  const bool live = state(now_s) == VehicleInputState::kLive;
  if (live != following_live_) {
    following_live_ = live;
    fade_start_s_ = now_s;
    fade_from_ = output_;
  }
  VehicleSample source;  // a rider at rest
  if (live) {
    source.specific_force_m_s2 = latest_->specific_force_m_s2;
    source.angular_velocity_rad_s = latest_->angular_velocity_rad_s;
  }
  const double w = RaisedCosine((now_s - fade_start_s_) / parameters_.fade_s);
  output_.t_s = now_s;
  output_.specific_force_m_s2 =
      fade_from_.specific_force_m_s2 + w * (source.specific_force_m_s2 - fade_from_.specific_force_m_s2);
  output_.angular_velocity_rad_s =
      fade_from_.angular_velocity_rad_s + w * (source.angular_velocity_rad_s - fade_from_.angular_velocity_rad_s);
  return output_;
}

}  // namespace edsp
