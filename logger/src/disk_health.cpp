#include "edsp/logger/disk_health.h"

#include <fmt/format.h>

#include "edsp/node/fault.h"

namespace edsp {

bool DiskHealth::Update(const LogWriterStats& w, std::int64_t now, fault_t* fault) {
  if (w.disk_failing && !failing_) {
    failing_ = true;
    dropped_at_failure_ = w.dropped;
    *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_ERROR,
                       fmt::format("{}; the file ends on a whole event and stays readable", w.last_error), now);
    return true;
  }
  if (!w.disk_failing && failing_) {
    failing_ = false;
    accounted_dropped_ = w.dropped;  // reported with this episode, not as a lag later
    *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_INFO,
                       fmt::format("{}: writing again; {} events dropped while the disk refused them", w.path,
                                   w.dropped - dropped_at_failure_),
                       now);
    return true;
  }
  if (w.dropped > accounted_dropped_ && !failing_ && !lag_reported_) {
    lag_reported_ = true;  // once: a disk that cannot keep up
    *fault = MakeFault("logger", "", FaultCode::kStorage, fault_t::SEVERITY_ERROR,
                       fmt::format("{} events dropped: the disk cannot keep up", w.dropped - accounted_dropped_), now);
    return true;
  }
  return false;
}

}  // namespace edsp
