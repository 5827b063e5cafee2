#pragma once
// edsp-cueing delay: each vehicle sample's delay from its sender to the
// drives, traced through a group's log (cueing_delay.h).
//   edsp-cueing delay --log RUN.lcmlog --sent SENT.csv [--json]
// SENT.csv is what `edsp-cueing send --sent-log` wrote. Prints how many
// samples were traced and the delay's p50, p99 and largest; exits 1 when
// none was (a log of another run, or of no cueing).

#include <string>

namespace edsp {

struct DelayOptions {
  std::string log_path;
  std::string sent_path;
  bool json = false;
};

int RunDelay(const DelayOptions& options);

}  // namespace edsp
