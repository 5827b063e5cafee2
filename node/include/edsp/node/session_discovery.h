#pragma once
// The session of the group commanding the platform, found from its own
// traffic: what a client (edsp-ctl, the Python Platform) addresses its
// requests to when it is not told.

#include <cstdint>

#include "edsp/transport/bus.h"

namespace edsp {

// The one session whose leg commands or setpoints are on `bus` within
// `timeout_s`. Throws std::runtime_error naming the bus when there are none
// (the group is not running there) or naming the sessions when there are
// several (two groups on one network). Its handlers stay subscribed for the
// bus's life.
std::int64_t DiscoverSession(Bus& bus, double timeout_s);

}  // namespace edsp
