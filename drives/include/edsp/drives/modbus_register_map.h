#pragma once
// The register map of edsp's Modbus TCP drives (docs/drives.md): six
// drives' CSP process images in holding registers, the commands (RxPDO) of
// all six in one block and their feedback (TxPDO) in another, so that one
// "read/write multiple registers" request (function 23) is a whole cycle.
// 32-bit values take two registers, high word first.

#include <array>
#include <cstdint>

#include "edsp/drives/csp_image.h"

namespace edsp::cia402::modbus_map {

inline constexpr int kDrives = 6;
inline constexpr int kRegistersPerDrive = 8;
inline constexpr int kCommandAddress = 0;                             // drive d's RxPDO at 0 + 8·d
inline constexpr int kFeedbackAddress = 256;                          // drive d's TxPDO at 256 + 8·d
inline constexpr int kBlockRegisters = kDrives * kRegistersPerDrive;  // 48
inline constexpr int kRegisterCount = kFeedbackAddress + kBlockRegisters;

using DriveRegisters = std::array<std::uint16_t, kRegistersPerDrive>;

// RxPDO: controlword, mode of operation, target position (hi, lo),
// velocity offset (hi, lo), two reserved (0).
DriveRegisters EncodeCommand(const CspCommand& command);
CspCommand DecodeCommand(const std::uint16_t* registers);
// TxPDO: statusword, mode display, position actual (hi, lo), velocity
// actual (hi, lo), error code, the drives' cycle count.
DriveRegisters EncodeFeedback(const CspFeedback& feedback);
CspFeedback DecodeFeedback(const std::uint16_t* registers);

}  // namespace edsp::cia402::modbus_map
