#pragma once
// edsp-cueing bench (deploy/edsp bench cueing): per algorithm the
// manoeuvres' perception errors (commanded and real, and over variants of
// them no setting was chosen on), a soak of random vehicle motion counting
// refused setpoints and the solve's time; their ratios; the OMCT.
//   edsp-cueing bench --config FILE --cueing FILE --manoeuvre FILE... [--rig-effects FILE]
//                     [--cycles 1000000] [--seed 1] [--variants 3] [--variant-seed 2026] [--json]

#include <cstdint>

#include "offline_command.h"

namespace edsp {

struct BenchOptions {
  OfflineOptions offline;
  std::int64_t cycles = 1'000'000;
  std::uint64_t seed = 1;
  int variants = 3;  // per manoeuvre, none tuned on
  std::uint64_t variant_seed = 2026;
};

int RunBench(const BenchOptions& options);

}  // namespace edsp
