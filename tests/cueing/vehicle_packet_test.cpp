// The vehicle's samples by either input: the UDP packet (what is sent is
// what is read, byte for byte as documented) and EDSP_VEHICLE's message
// (through LCM's own encoding), every way a sender gets either wrong refused
// by name, and one sample read the same by both.
#include "edsp/cueing/vehicle_packet.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/cueing/vehicle_message.h"

namespace edsp {
namespace {

VehiclePacket Sample(std::mt19937& random) {
  std::uniform_real_distribution<double> force(-30.0, 30.0), omega(-3.0, 3.0), alpha(-40.0, 40.0);
  VehiclePacket p;
  p.command = static_cast<CueCommand>(1 + random() % 4);
  p.sequence = static_cast<std::uint32_t>(random());
  p.time_s = std::uniform_real_distribution<double>(0.0, 1e5)(random);
  p.specific_force_m_s2 = Vector3(force(random), force(random), force(random));
  p.angular_velocity_rad_s = Vector3(omega(random), omega(random), omega(random));
  if (random() % 2 == 0) p.angular_acceleration_rad_s2 = Vector3(alpha(random), alpha(random), alpha(random));
  return p;
}

std::string Refusal(const std::array<std::uint8_t, kVehiclePacketBytes>& bytes) {
  const ParsedVehiclePacket parsed = ParseVehiclePacket(bytes.data(), bytes.size());
  return parsed.packet ? "(accepted)" : parsed.error;
}

TEST(VehiclePacket, WhatIsSentIsWhatIsReadToFloatPrecision) {
  std::mt19937 random(20261205);
  for (int i = 0; i < 1000; ++i) {
    const VehiclePacket sent = Sample(random);
    const auto bytes = EncodeVehiclePacket(sent);
    const ParsedVehiclePacket parsed = ParseVehiclePacket(bytes.data(), bytes.size());
    ASSERT_TRUE(parsed.packet) << parsed.error;
    const VehiclePacket& read = *parsed.packet;
    EXPECT_EQ(read.command, sent.command);
    EXPECT_EQ(read.sequence, sent.sequence);
    EXPECT_EQ(read.time_s, sent.time_s);  // float64 on the wire
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(read.specific_force_m_s2(axis),
                static_cast<double>(static_cast<float>(sent.specific_force_m_s2(axis))));
      EXPECT_EQ(read.angular_velocity_rad_s(axis),
                static_cast<double>(static_cast<float>(sent.angular_velocity_rad_s(axis))));
    }
    ASSERT_EQ(read.angular_acceleration_rad_s2.has_value(), sent.angular_acceleration_rad_s2.has_value());
    if (sent.angular_acceleration_rad_s2) {
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ((*read.angular_acceleration_rad_s2)(axis),
                  static_cast<double>(static_cast<float>((*sent.angular_acceleration_rad_s2)(axis))));
      }
    }
  }
}

TEST(VehiclePacket, TheBytesAreTheDocumentedLayout) {
  VehiclePacket p;
  p.command = CueCommand::kFreeze;
  p.sequence = 0x01020304;
  p.time_s = 2.5;
  p.specific_force_m_s2 = Vector3(-4.5, 0.25, 9.75);
  p.angular_velocity_rad_s = Vector3(0.5, -0.125, 1.0);
  const auto bytes = EncodeVehiclePacket(p);
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(bytes.data()), 4), "EDSV");
  EXPECT_EQ(bytes[4], 1);  // version, little-endian
  EXPECT_EQ(bytes[5], 0);
  EXPECT_EQ(bytes[6], 3);     // freeze
  EXPECT_EQ(bytes[8], 0x04);  // sequence, least significant byte first
  EXPECT_EQ(bytes[11], 0x01);
  EXPECT_EQ(bytes[12], 0);  // no angular acceleration
  double time;
  std::memcpy(&time, bytes.data() + 16, 8);  // this host is little-endian, as the wire
  EXPECT_EQ(time, 2.5);
  float fx, wz;
  std::memcpy(&fx, bytes.data() + 24, 4);
  std::memcpy(&wz, bytes.data() + 44, 4);
  EXPECT_EQ(fx, -4.5f);
  EXPECT_EQ(wz, 1.0f);
}

TEST(VehiclePacket, EveryWayASenderGetsItWrongIsRefusedByName) {
  const auto good = EncodeVehiclePacket(VehiclePacket{});
  EXPECT_EQ(Refusal(good), "(accepted)");
  EXPECT_NE(ParseVehiclePacket(good.data(), 59).error.find("60 bytes, this one 59"), std::string::npos);
  std::array<std::uint8_t, 61> longer{};
  std::copy(good.begin(), good.end(), longer.begin());
  EXPECT_NE(ParseVehiclePacket(longer.data(), longer.size()).error.find("this one 61"), std::string::npos);
  auto bad = good;
  bad[0] = 'X';
  EXPECT_NE(Refusal(bad).find("is not \"EDSV\""), std::string::npos);
  bad = good;
  bad[4] = 2;
  EXPECT_NE(Refusal(bad).find("version 2"), std::string::npos);
  bad = good;
  bad[6] = 9;
  EXPECT_NE(Refusal(bad).find("command 9"), std::string::npos);
  bad = good;
  bad[12] = 2;
  EXPECT_NE(Refusal(bad).find("flags 0x2"), std::string::npos);
  VehiclePacket p;
  p.time_s = std::numeric_limits<double>::infinity();
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("time_s = inf"), std::string::npos);
  p = VehiclePacket{};
  p.time_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("time_s = nan"), std::string::npos);
  p = VehiclePacket{};
  p.specific_force_m_s2.x() = -60.0;  // beyond 5 g
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("specific force x = -60 m/s²"), std::string::npos);
  p = VehiclePacket{};
  p.angular_acceleration_rad_s2 = Vector3(std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0);
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("angular acceleration x = nan"), std::string::npos);
  p = VehiclePacket{};
  p.specific_force_m_s2.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("specific force y = nan"), std::string::npos);
  p = VehiclePacket{};
  p.angular_velocity_rad_s.z() = 90.0;  // deg/s sent as rad/s
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("angular velocity z = 90 rad/s"), std::string::npos);
  p = VehiclePacket{};
  p.angular_acceleration_rad_s2 = Vector3(0.0, 100.0, 0.0);
  EXPECT_NE(Refusal(EncodeVehiclePacket(p)).find("angular acceleration y = 100"), std::string::npos);
}

// `message` through LCM's encoding and back, then read as the cueing reads it.
ParsedVehiclePacket OverTheBus(const vehicle_motion_t& message) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  EXPECT_EQ(message.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  vehicle_motion_t received;
  EXPECT_EQ(received.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return ReadVehicleMessage(received);
}

std::string Refusal(const vehicle_motion_t& message) {
  const ParsedVehiclePacket parsed = OverTheBus(message);
  return parsed.packet ? "(accepted)" : parsed.error;
}

void ExpectSame(const VehiclePacket& read, const VehiclePacket& sent) {
  EXPECT_EQ(read.command, sent.command);
  EXPECT_EQ(read.sequence, sent.sequence);
  EXPECT_EQ(read.time_s, sent.time_s);
  EXPECT_EQ(read.specific_force_m_s2, sent.specific_force_m_s2);
  EXPECT_EQ(read.angular_velocity_rad_s, sent.angular_velocity_rad_s);
  ASSERT_EQ(read.angular_acceleration_rad_s2.has_value(), sent.angular_acceleration_rad_s2.has_value());
  if (sent.angular_acceleration_rad_s2) {
    EXPECT_EQ(*read.angular_acceleration_rad_s2, *sent.angular_acceleration_rad_s2);
  }
}

TEST(VehicleMessage, WhatIsSentOnTheBusIsWhatIsReadExactlyAndAsTheUdpPacketReadsIt) {
  std::mt19937 random(4711);
  for (int i = 0; i < 1000; ++i) {
    const VehiclePacket sent = Sample(random);
    const vehicle_motion_t message = VehicleMessage(sent, 78, 1'700'000'000'000'000 + i);
    EXPECT_EQ(message.session_id, 78);
    const ParsedVehiclePacket read = OverTheBus(message);
    ASSERT_TRUE(read.packet) << read.error;
    ExpectSame(*read.packet, sent);  // float64 on the bus: no rounding
    // The packet's float32 sample, sent both ways, is one sample to the cueing.
    const auto bytes = EncodeVehiclePacket(sent);
    const ParsedVehiclePacket by_udp = ParseVehiclePacket(bytes.data(), bytes.size());
    ASSERT_TRUE(by_udp.packet) << by_udp.error;
    const ParsedVehiclePacket by_bus = OverTheBus(VehicleMessage(*by_udp.packet, 78, 0));
    ASSERT_TRUE(by_bus.packet) << by_bus.error;
    ExpectSame(*by_bus.packet, *by_udp.packet);
  }
}

TEST(VehicleMessage, EveryWayASenderGetsItWrongIsRefusedByNameAsOnUdp) {
  const vehicle_motion_t good = VehicleMessage(VehiclePacket{}, 1, 0);
  EXPECT_EQ(Refusal(good), "(accepted)");
  vehicle_motion_t bad = good;
  bad.command = 0;
  EXPECT_NE(Refusal(bad).find("command 0: must be 1 engage"), std::string::npos);
  bad.command = 5;
  EXPECT_NE(Refusal(bad).find("command 5"), std::string::npos);
  bad = good;
  bad.seq = -1;
  EXPECT_NE(Refusal(bad).find("seq -1: must be 0…4294967295"), std::string::npos);
  bad.seq = std::int64_t{1} << 32;
  EXPECT_NE(Refusal(bad).find("seq 4294967296"), std::string::npos);
  bad.seq = 4294967295;
  EXPECT_EQ(Refusal(bad), "(accepted)");
  bad = good;
  bad.time_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(Refusal(bad).find("time_s = nan"), std::string::npos);
  bad = good;
  bad.specific_force[1] = std::numeric_limits<double>::infinity();
  EXPECT_NE(Refusal(bad).find("specific force y = inf"), std::string::npos);
  bad = good;
  bad.angular_velocity[2] = 90.0;  // deg/s sent as rad/s
  EXPECT_NE(Refusal(bad).find("angular velocity z = 90 rad/s"), std::string::npos);
  // The angular acceleration is read only when flagged, and then checked.
  bad = good;
  bad.angular_acceleration[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Refusal(bad), "(accepted)");
  bad.has_angular_acceleration = true;
  EXPECT_NE(Refusal(bad).find("angular acceleration x = nan"), std::string::npos);
}

}  // namespace
}  // namespace edsp
