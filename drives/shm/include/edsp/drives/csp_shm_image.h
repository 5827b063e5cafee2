#pragma once
// Six CiA 402 drives' CSP process image in shared memory: one RxPDO record
// (master → drives) and one TxPDO record (drives → master) per cycle, each
// on its own edsp seqlock ring. The records are the PDO mapping of
// docs/drives.md (6040h, 6060h, 607Ah, 60B1h out; 6041h, 6061h, 6064h,
// 606Ch, 603Fh and the cycle count in), so whatever serves the drives'
// side (edsp-drive-sim --serve shm, or an EtherCAT master process copying
// its PDOs) serves the bridge without touching it.
//
//   <prefix>.cia402.rxpdo   written by the master (the bridge)
//   <prefix>.cia402.txpdo   written by the drives' side, once per drive cycle

#include <chrono>
#include <cstdint>
#include <string>

#include "edsp/drives/csp_link.h"
#include "edsp/transport/shm_segment.h"

namespace edsp::cia402 {

struct CspRxImage {
  std::int64_t utime;  // when the master wrote it
  std::int64_t cycle;  // the master's cycle count
  CspCommand drives[kCabinetDrives];
};

struct CspTxImage {
  std::int64_t utime;                  // when the drives latched it
  CspFeedback drives[kCabinetDrives];  // cycle_count: the drives' cycle (mod 2^16)
};

// The images' utime: wall clock, µs since the epoch, like every edsp stamp.
inline std::int64_t ImageUtimeNow() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Layout fingerprints checked by the segments (bump on any change).
inline constexpr std::int64_t kCspRxImageFingerprint = 0x4544535043525831;  // "EDSPCRX1"
inline constexpr std::int64_t kCspTxImageFingerprint = 0x4544535043545831;  // "EDSPCTX1"

inline ShmChannelSpec CspRxSpec(const std::string& prefix, mode_t permissions) {
  return {prefix + ".cia402.rxpdo", kCspRxImageFingerprint, 16, sizeof(CspRxImage), permissions};
}
inline ShmChannelSpec CspTxSpec(const std::string& prefix, mode_t permissions) {
  return {prefix + ".cia402.txpdo", kCspTxImageFingerprint, 16, sizeof(CspTxImage), permissions};
}

}  // namespace edsp::cia402
