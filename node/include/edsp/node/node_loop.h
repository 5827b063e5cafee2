#pragma once
// How a node's loop runs, written once for every node: on a clock (one
// cycle at each tick, the bus's input taken while it waits for the tick) or
// polled (the bus handled for a while, then a poll). Each loop owns what its
// cycle or poll does and its reporting (NodeReporting); these own the
// waiting, the order and the stop.

#include <chrono>
#include <cstdint>
#include <functional>

#include "edsp/node/runtime.h"
#include "edsp/transport/bus.h"

namespace edsp {

// One cycle at `now_utime` (the wall clock at its start) with the clock's
// count of missed ticks; false ends the loop.
using NodeCycle = std::function<bool(std::int64_t now_utime, std::int64_t missed_ticks)>;

// Until stop() is true or a cycle returns false: the bus handled until the
// clock's next tick, then a cycle. A cycle that overran its period (a slow
// drive exchange, a starved host) leaves no time to wait in: what came
// meanwhile is still taken before the next cycle, or a loop that keeps
// overrunning never reads its input and latches on a stream that is there.
void RunOnClock(Bus& bus, CycleClock& clock, const std::function<bool()>& stop, const NodeCycle& cycle);
// The same for a loop whose input does not come on the bus (the rig's
// commands come through its process image): it sleeps until each tick.
void RunOnClock(CycleClock& clock, const std::function<bool()>& stop, const NodeCycle& cycle);
// Until stop() is true: the bus handled for up to `interval`, then
// poll(now).
void RunPolled(Bus& bus, std::chrono::microseconds interval, const std::function<bool()>& stop,
               const std::function<void(std::int64_t now_utime)>& poll);

}  // namespace edsp
