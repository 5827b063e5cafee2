#pragma once
// The master's per-drive logic each cycle, whatever carries the image:
// enable the drive through the CiA 402 state machine, and never hand a CSP
// drive a target it would jump to (until operation is enabled, and whenever
// the master has nothing valid to send, the target is where the drive is).

#include <cstdint>
#include <optional>

#include "edsp/drives/cia402.h"
#include "edsp/drives/csp_image.h"

namespace edsp::cia402 {

// `wanted_counts` empty: hold the drive where it is. `previous` is the
// controlword written last cycle (a fault reset must be an edge).
CspCommand NextCspCommand(const CspFeedback& feedback, std::uint16_t previous,
                          std::optional<std::int32_t> wanted_counts, std::int32_t velocity_offset = 0);

}  // namespace edsp::cia402
