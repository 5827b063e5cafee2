#pragma once
// The timing a group's nodes rely on from each other, once: the bridge acts
// on it, the rig emulator models drives that honour it, the logger's stall
// watch and measurement export read a log by it (docs/interfaces.md §1).

#include <cstdint>

namespace edsp::timing {

// Every 1 kHz stream's period: setpoints, leg commands, drive readings.
inline constexpr std::int64_t kCycleUs = 1000;

// Drives continue a setpoint along its velocity feed-forward for at most
// this long; past it the bridge, itself on time, writes them one of its own
// every cycle (the last command's motion, stamped for that instant).
inline constexpr std::int64_t kFeedForwardLapseUs = 2500;

// Leg commands late while the bridge keeps its time: the last command's
// motion is continued this long, then brought to rest (ride_through.h).
inline constexpr std::int64_t kRideThroughUs = 10000;

// The same, in seconds, for the physics and the log's arithmetic.
inline constexpr double kFeedForwardLapseS = static_cast<double>(kFeedForwardLapseUs) * 1e-6;
inline constexpr double kRideThroughS = static_cast<double>(kRideThroughUs) * 1e-6;

}  // namespace edsp::timing
