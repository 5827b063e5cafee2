#include "edsp/node/node_loop.h"

namespace edsp {

void RunOnClock(Bus& bus, CycleClock& clock, const std::function<bool()>& stop, const NodeCycle& cycle) {
  while (!stop()) {
    bool handled = false;
    for (auto left = clock.UntilNext(); left.count() > 0 && !stop(); left = clock.UntilNext()) {
      bus.Handle(std::chrono::duration_cast<std::chrono::microseconds>(left));
      handled = true;
    }
    if (!handled) bus.Handle(std::chrono::microseconds(0));
    clock.WaitNext();
    if (!cycle(UtimeNow(), clock.missed())) return;
  }
}

void RunOnClock(CycleClock& clock, const std::function<bool()>& stop, const NodeCycle& cycle) {
  while (!stop()) {
    clock.WaitNext();
    if (!cycle(UtimeNow(), clock.missed())) return;
  }
}

void RunPolled(Bus& bus, std::chrono::microseconds interval, const std::function<bool()>& stop,
               const std::function<void(std::int64_t now_utime)>& poll) {
  while (!stop()) {
    bus.Handle(interval);
    poll(UtimeNow());
  }
}

}  // namespace edsp
