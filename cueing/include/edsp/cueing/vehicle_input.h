#pragma once
// The vehicle's samples as the cueing uses them: packets refused when
// they arrive out of order, repeated, or with the vehicle's time going
// back (the first packet after a loss starts a new stream); and when none
// has come for `timeout_s` the input fades to a rider
// at rest (gravity, no rotation) over `fade_s` along a raised cosine, so
// the washout brings the platform home with no step in acceleration.
// Input that comes back fades in the same way.

#include <cstdint>
#include <optional>
#include <string>

#include "edsp/cueing/vehicle_packet.h"

namespace edsp {

struct VehicleInputParameters {
  double timeout_s = 0.1;  // no packet for this long: lost
  double fade_s = 1.0;     // to rest, or back to the live input
};

enum class VehicleInputState { kWaiting, kLive, kLost };
const char* VehicleInputStateName(VehicleInputState state);

class VehicleInput {
 public:
  // Throws std::invalid_argument naming a parameter not finite and > 0.
  explicit VehicleInput(const VehicleInputParameters& parameters);

  // A packet received at `now_s` (the receiver's monotonic clock, s):
  // nothing if accepted, else why not ("sequence 41 after 42: out of
  // order or repeated").
  std::optional<std::string> Accept(const VehiclePacket& packet, double now_s);

  // The sample to cue at `now_s` (non-decreasing between calls).
  VehicleSample At(double now_s);

  VehicleInputState state(double now_s) const;
  // The command of the last packet accepted (nothing before the first).
  std::optional<CueCommand> command() const;
  // The sequence of the last packet accepted (0 before the first).
  std::uint32_t latest_sequence() const { return latest_ ? latest_->sequence : 0; }
  // Packets missing from the sequence so far.
  std::uint64_t missed_packets() const { return missed_packets_; }

 private:
  VehicleInputParameters parameters_;
  std::optional<VehiclePacket> latest_;
  double latest_receive_s_ = 0.0;
  std::uint64_t missed_packets_ = 0;
  // The fade: from the output when the source last changed, to the source.
  bool following_live_ = false;
  double fade_start_s_ = -1e300;
  VehicleSample fade_from_;
  VehicleSample output_;
};

}  // namespace edsp
