#include "edsp/drives/modbus_register_map.h"

namespace edsp::cia402::modbus_map {
namespace {

std::uint16_t High(std::int32_t value) { return static_cast<std::uint16_t>(static_cast<std::uint32_t>(value) >> 16); }
std::uint16_t Low(std::int32_t value) {
  return static_cast<std::uint16_t>(static_cast<std::uint32_t>(value) & 0xFFFFu);
}
std::int32_t Join(std::uint16_t high, std::uint16_t low) {
  return static_cast<std::int32_t>((static_cast<std::uint32_t>(high) << 16) | low);
}
std::uint16_t FromInt8(std::int8_t value) { return static_cast<std::uint16_t>(static_cast<std::int16_t>(value)); }
std::int8_t ToInt8(std::uint16_t value) { return static_cast<std::int8_t>(static_cast<std::uint8_t>(value & 0xFFu)); }

}  // namespace

DriveRegisters EncodeCommand(const CspCommand& c) {
  return {c.controlword,
          FromInt8(c.mode_of_operation),
          High(c.target_position),
          Low(c.target_position),
          High(c.velocity_offset),
          Low(c.velocity_offset),
          0,
          0};
}

CspCommand DecodeCommand(const std::uint16_t* r) {
  CspCommand c;
  c.controlword = r[0];
  c.mode_of_operation = ToInt8(r[1]);
  c.target_position = Join(r[2], r[3]);
  c.velocity_offset = Join(r[4], r[5]);
  return c;
}

DriveRegisters EncodeFeedback(const CspFeedback& f) {
  return {f.statusword,
          FromInt8(f.mode_display),
          High(f.position_actual),
          Low(f.position_actual),
          High(f.velocity_actual),
          Low(f.velocity_actual),
          f.error_code,
          f.cycle_count};
}

CspFeedback DecodeFeedback(const std::uint16_t* r) {
  CspFeedback f;
  f.statusword = r[0];
  f.mode_display = ToInt8(r[1]);
  f.position_actual = Join(r[2], r[3]);
  f.velocity_actual = Join(r[4], r[5]);
  f.error_code = r[6];
  f.cycle_count = r[7];
  return f;
}

}  // namespace edsp::cia402::modbus_map
