// Drive units: motor angle ↔ counts round trips, refusal of what does not
// fit a drive's 32 bits (never a wrapped target), and the Modbus register
// map against values encoded by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "edsp/drives/cia402.h"
#include "edsp/drives/csp_image.h"
#include "edsp/drives/modbus_register_map.h"

namespace edsp::cia402 {
namespace {

// 2^20 counts per motor turn.
DriveScaling Encoder(int direction = 1, std::int32_t offset = 0) {
  DriveScaling s;
  s.counts_per_rad = 1048576.0 / (2.0 * M_PI);
  s.direction = direction;
  s.offset_counts = offset;
  return s;
}

TEST(DriveScaling, AnglesRoundTripWithinHalfACount) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-400.0, 400.0);  // ±64 turns
  for (int direction : {1, -1}) {
    const DriveScaling s = Encoder(direction, -123456);
    for (int k = 0; k < 1000; ++k) {
      const double a = angle(random);
      const auto counts = s.ToCounts(a);
      ASSERT_TRUE(counts.has_value());
      EXPECT_NEAR(s.ToAngle(*counts), a, 0.5 / s.counts_per_rad);
    }
  }
  EXPECT_EQ(*Encoder(1, 100).ToCounts(0.0), 100) << "home is the offset";
  EXPECT_EQ(*Encoder(-1).ToCounts(2.0 * M_PI), -1048576) << "a reversed motor counts down";
  EXPECT_EQ(*Encoder().ToCountsPerSecond(2.0 * M_PI), 1048576);
  EXPECT_DOUBLE_EQ(Encoder(-1).ToRate(-1048576), 2.0 * M_PI);
}

TEST(DriveScaling, WhatDoesNotFitADrivesPositionIsRefusedNotWrapped) {
  const DriveScaling s = Encoder();
  EXPECT_FALSE(s.ToCounts(std::numeric_limits<double>::quiet_NaN()).has_value());
  EXPECT_FALSE(s.ToCounts(std::numeric_limits<double>::infinity()).has_value());
  EXPECT_FALSE(s.ToCounts(2.0 * M_PI * 4096.0).has_value()) << "2^32 counts";
  EXPECT_FALSE(s.ToCounts(-2.0 * M_PI * 2049.0).has_value());
  EXPECT_TRUE(s.ToCounts(2.0 * M_PI * 2047.0).has_value());
}

TEST(DriveScaling, AbsurdScalingsAreNamed) {
  DriveScaling s = Encoder();
  EXPECT_EQ(s.Problem(), std::nullopt);
  s.counts_per_rad = 0.0;
  EXPECT_NE(s.Problem().value_or("").find("counts_per_rad"), std::string::npos);
  s = Encoder();
  s.counts_per_rad = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(s.Problem().value_or("").find("counts_per_rad"), std::string::npos);
  s = Encoder();
  s.direction = 0;
  EXPECT_NE(s.Problem().value_or("").find("direction"), std::string::npos);
}

TEST(ModbusRegisterMap, CommandsAndFeedbackAsEncodedByHand) {
  CspCommand c;
  c.controlword = 0x000F;
  c.mode_of_operation = kModeCyclicSynchronousPosition;
  c.target_position = -2;  // 0xFFFFFFFE: high word first
  c.velocity_offset = 0x12345678;
  EXPECT_EQ(modbus_map::EncodeCommand(c),
            (modbus_map::DriveRegisters{0x000F, 0x0008, 0xFFFF, 0xFFFE, 0x1234, 0x5678, 0, 0}));
  CspFeedback f;
  f.statusword = 0x0237;
  f.mode_display = -1;
  f.position_actual = 65536;
  f.velocity_actual = -65536;
  f.error_code = 0x8611;
  f.cycle_count = 0xBEEF;
  EXPECT_EQ(modbus_map::EncodeFeedback(f),
            (modbus_map::DriveRegisters{0x0237, 0xFFFF, 0x0001, 0x0000, 0xFFFF, 0x0000, 0x8611, 0xBEEF}));
}

TEST(ModbusRegisterMap, EveryValueRoundTrips) {
  std::mt19937 random(11);
  std::uniform_int_distribution<std::int32_t> any32(std::numeric_limits<std::int32_t>::min(),
                                                    std::numeric_limits<std::int32_t>::max());
  std::uniform_int_distribution<int> any16(0, 0xFFFF), any8(-128, 127);
  for (int k = 0; k < 10000; ++k) {
    CspCommand c;
    c.controlword = static_cast<std::uint16_t>(any16(random));
    c.mode_of_operation = static_cast<std::int8_t>(any8(random));
    c.target_position = any32(random);
    c.velocity_offset = any32(random);
    const CspCommand c2 = modbus_map::DecodeCommand(modbus_map::EncodeCommand(c).data());
    ASSERT_EQ(c2.controlword, c.controlword);
    ASSERT_EQ(c2.mode_of_operation, c.mode_of_operation);
    ASSERT_EQ(c2.target_position, c.target_position);
    ASSERT_EQ(c2.velocity_offset, c.velocity_offset);
    CspFeedback f;
    f.statusword = static_cast<std::uint16_t>(any16(random));
    f.mode_display = static_cast<std::int8_t>(any8(random));
    f.position_actual = any32(random);
    f.velocity_actual = any32(random);
    f.error_code = static_cast<std::uint16_t>(any16(random));
    f.cycle_count = static_cast<std::uint16_t>(any16(random));
    const CspFeedback f2 = modbus_map::DecodeFeedback(modbus_map::EncodeFeedback(f).data());
    ASSERT_EQ(f2.statusword, f.statusword);
    ASSERT_EQ(f2.mode_display, f.mode_display);
    ASSERT_EQ(f2.position_actual, f.position_actual);
    ASSERT_EQ(f2.velocity_actual, f.velocity_actual);
    ASSERT_EQ(f2.error_code, f.error_code);
    ASSERT_EQ(f2.cycle_count, f.cycle_count);
  }
}

TEST(ModbusRegisterMap, OneCycleFitsOneReadWriteRequest) {
  // Function 23 writes at most 121 and reads at most 125 registers.
  EXPECT_LE(modbus_map::kBlockRegisters, 121);
  EXPECT_GE(modbus_map::kFeedbackAddress, modbus_map::kCommandAddress + modbus_map::kBlockRegisters);
}

}  // namespace
}  // namespace edsp::cia402
