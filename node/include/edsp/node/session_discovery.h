#pragma once
// The session of the group commanding the platform, found from its own
// traffic: what a client (edsp-ctl, the Python Platform) addresses its
// requests to when it is not told.

#include <cstdint>
#include <stdexcept>

#include "edsp/transport/bus.h"

namespace edsp {

// No one session to address: none within the timeout, or several.
class SessionNotFound : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The one session whose leg commands or setpoints are on `bus` within
// `timeout_s`. Throws SessionNotFound naming the bus when there are none
// (the group is not running there) or naming the sessions when there are
// several (two groups on one network). Its handlers stay subscribed for the
// bus's life.
std::int64_t DiscoverSession(Bus& bus, double timeout_s);

}  // namespace edsp
