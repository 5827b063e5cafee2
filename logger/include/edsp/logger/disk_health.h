#pragma once
// The disk's episodes as the logger reports them on EDSP_FAULT: one error
// when writing starts failing, one info when it works again with what was
// lost in between, and one error (once) when events were dropped because
// the disk could not keep up.

#include <cstdint>

#include "edsp/fault_t.hpp"
#include "edsp/logger/log_writer.h"

namespace edsp {

class DiskHealth {
 public:
  // Looks at the writer's newest stats; true (and `fault` filled) when an
  // episode starts or ends.
  bool Update(const LogWriterStats& w, std::int64_t now, fault_t* fault);
  bool failing() const { return failing_; }

 private:
  bool failing_ = false;
  bool lag_reported_ = false;
  std::int64_t dropped_at_failure_ = 0;
  std::int64_t accounted_dropped_ = 0;  // drops a full-disk episode already reported
};

}  // namespace edsp
