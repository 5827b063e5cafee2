#pragma once
// Messages missing between two `seq` numbers of one publisher. The numbers
// come from outside (a foreign or corrupt packet can carry any int64), so
// the arithmetic never overflows, a publisher that restarted (seq going
// back) is no loss, and a jump beyond any real run (2^32 messages: 50 days
// at 1 kHz) is a foreign number, not a loss.

#include <cstdint>

namespace edsp {

inline constexpr std::int64_t kImplausibleSeqGap = std::int64_t{1} << 32;

inline std::int64_t SeqGap(std::int64_t last_seq, std::int64_t seq) {
  if (last_seq < 0 || seq <= last_seq) return 0;
  const std::int64_t gap = seq - last_seq - 1;  // both >= 0: no overflow
  return gap < kImplausibleSeqGap ? gap : 0;
}

}  // namespace edsp
