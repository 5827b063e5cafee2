#pragma once
// Messages missing between two `seq` numbers of one publisher. The numbers
// come from outside (a foreign or corrupt packet can carry any int64), so
// the arithmetic never overflows, a publisher that restarted (seq going
// back) is no loss, and a jump beyond any real run (2^32 messages: 50 days
// at 1 kHz) is a foreign number, not a loss.

#include <cstdint>
#include <unordered_map>

namespace edsp {

inline constexpr std::int64_t kImplausibleSeqGap = std::int64_t{1} << 32;

inline std::int64_t SeqGap(std::int64_t last_seq, std::int64_t seq) {
  if (last_seq < 0 || seq <= last_seq) return 0;
  const std::int64_t gap = seq - last_seq - 1;  // both >= 0: no overflow
  return gap < kImplausibleSeqGap ? gap : 0;
}

// The messages one channel lost, per sending session: two groups on one
// network (one of them foreign, refused downstream) interleave their streams
// on a channel, and counting gaps across them would report millions of
// losses. Messages without a session count as session 0.
class SeqTracker {
 public:
  // The messages missing before this one (SeqGap), and remembers it.
  std::int64_t Count(std::int64_t session, std::int64_t seq) {
    if (last_by_session_.size() > kMaxSessions) last_by_session_.clear();  // a flood of sessions: start over
    std::int64_t& last = last_by_session_.try_emplace(session, -1).first->second;
    const std::int64_t gap = SeqGap(last, seq);
    last = seq;  // a restarted publisher (seq going back) is not a gap
    return gap;
  }

 private:
  static constexpr std::size_t kMaxSessions = 64;
  std::unordered_map<std::int64_t, std::int64_t> last_by_session_;
};

}  // namespace edsp
