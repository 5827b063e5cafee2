// edsp-cueing's loop on a bus (memq://, in process) reading EDSP_VEHICLE:
// a message of this session stamped now engages (the planner is asked);
// one of another session, or stamped a minute ago (a log of this session
// replayed later), is refused with a fault naming why and asks nothing;
// a flood within one cycle is cut to the queue's bound and said. Reading
// a UDP socket (loopback), the samples it took go out on EDSP_VEHICLE
// stamped at the cycle that took them, the refused ones do not.
#include "edsp/cueing/cueing_loop.h"

#include <limits>
#include <string>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "edsp/channels.h"
#include "edsp/cueing/vehicle_message.h"
#include "edsp/fault_t.hpp"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/motion_request_t.hpp"
#include "edsp/node/build_paths.h"
#include "memq_bus.h"  // tests/support

namespace edsp {
namespace {

constexpr std::int64_t kSession = 4;
constexpr std::int64_t kNow = 1'800'000'000'000'000;

struct Fixture {
  Fixture() {
    bus.Subscribe<motion_request_t>(channel::kMotionRequest,
                                    [this](const motion_request_t& r) { requests.push_back(r); });
    bus.Subscribe<fault_t>(channel::kFault, [this](const fault_t& f) { faults.push_back(f); });
  }
  static CueingLoopOptions Options() {
    CueingLoopOptions options;
    options.session_id = kSession;
    options.vehicle_on_bus = true;
    options.input_name = channel::kVehicle;
    return options;
  }
  void Send(std::int64_t session, std::int64_t stamp, std::uint32_t sequence) {
    VehiclePacket packet;
    packet.sequence = sequence;
    packet.time_s = sequence * 1e-3;
    vehicle.Publish(VehicleMessage(packet, session, stamp));
  }
  void Cycle(std::int64_t now) {
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
    loop.RunCycle(now, 0);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  }
  std::string Reasons() const {
    std::string all;
    for (const fault_t& f : faults) all += f.reason + "\n";
    return all;
  }

  Bus bus{test_support::MemqConfig("cueing_loop")};
  CueingConfig config{LoadCueingConfig(SourceDir() + "/config/cueing.toml")};
  CueingSource source{config, PlatformModel(Huang2021Config()).home_pose().ToVector()};
  CueingLoop loop{bus, source, nullptr, Options()};
  Bus::Publisher<vehicle_motion_t> vehicle{bus.Advertise<vehicle_motion_t>(channel::kVehicle)};
  std::vector<motion_request_t> requests;
  std::vector<fault_t> faults;
};

TEST(CueingLoopOnTheBus, AMessageOfThisSessionStampedNowEngages) {
  Fixture f;
  f.Send(kSession, kNow, 1);
  f.Cycle(kNow + 500);
  ASSERT_EQ(f.requests.size(), 1u) << f.Reasons();
  EXPECT_EQ(f.requests[0].kind, motion_request_t::KIND_ENGAGE);
  EXPECT_EQ(f.requests[0].session_id, kSession);
}

TEST(CueingLoopOnTheBus, AnotherSessionsOrAnOldStampIsRefusedByNameAndAsksNothing) {
  Fixture f;
  // Cycles 200 ms apart: each fault its own, past the reporting's throttle.
  f.Send(kSession + 1, kNow, 1);
  f.Cycle(kNow);
  f.Send(kSession, kNow + 200'000 - 60'000'000, 2);  // this session's log, replayed a minute on
  f.Cycle(kNow + 200'000);
  f.Send(kSession, kNow + 400'000 + 60'000'000, 3);  // a clock a minute ahead
  f.Cycle(kNow + 400'000);
  EXPECT_TRUE(f.requests.empty()) << "engaged by a message it should refuse";
  const std::string reasons = f.Reasons();
  EXPECT_NE(reasons.find("vehicle message of session 5 refused: this group's is 4"), std::string::npos) << reasons;
  EXPECT_NE(reasons.find("vehicle message seq 2 stamped 60.0 s before this node's clock refused"), std::string::npos)
      << reasons;
  EXPECT_NE(reasons.find("seq 3 stamped 60.0 s after"), std::string::npos) << reasons;
}

TEST(CueingLoopOnTheBus, AFloodWithinOneCycleIsCutToTheQueuesBoundAndSaid) {
  Fixture f;
  for (std::uint32_t k = 1; k <= 1005; ++k) f.Send(kSession, kNow, k);
  f.Cycle(kNow + 500);
  EXPECT_NE(f.Reasons().find("5 vehicle messages dropped: more than 1000 came within one cycle"), std::string::npos)
      << f.Reasons();
  EXPECT_EQ(f.requests.size(), 1u) << "the samples kept still engage";
}

// A vehicle host on loopback: each packet a datagram to `port`.
void SendDatagram(std::uint16_t port, const VehiclePacket& packet) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const auto bytes = EncodeVehiclePacket(packet);
  EXPECT_EQ(::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to),
            static_cast<ssize_t>(bytes.size()));
  ::close(fd);
}

TEST(CueingLoopOnUdp, TheSamplesTakenGoOutOnTheBusStampedWhenTheyCameAndTheRefusedDoNot) {
  Bus bus{test_support::MemqConfig("cueing_loop_udp")};
  const CueingConfig config = LoadCueingConfig(SourceDir() + "/config/cueing.toml");
  CueingSource source{config, PlatformModel(Huang2021Config()).home_pose().ToVector()};
  VehicleSocket socket("127.0.0.1", 0);
  CueingLoopOptions options;
  options.session_id = kSession;
  options.input_name = "UDP 127.0.0.1";
  CueingLoop loop{bus, source, &socket, options};
  std::vector<vehicle_motion_t> heard;
  bus.Subscribe<vehicle_motion_t>(channel::kVehicle, [&](const vehicle_motion_t& m) { heard.push_back(m); });
  auto cycle = [&](std::int64_t now) {
    loop.RunCycle(now, 0);
    while (bus.Handle(std::chrono::milliseconds(0)) > 0) {
    }
  };

  VehiclePacket taken;
  taken.sequence = 7;
  taken.time_s = 0.007;
  taken.specific_force_m_s2 = Vector3(1.5, -0.25, 9.5);
  taken.angular_velocity_rad_s = Vector3(0.015625, 0.03125, -0.0625);  // exact in the packet's floats
  SendDatagram(socket.port(), taken);
  VehiclePacket refused = taken;
  refused.sequence = 8;
  refused.specific_force_m_s2.x() = std::numeric_limits<double>::quiet_NaN();
  SendDatagram(socket.port(), refused);  // by its parser
  VehiclePacket late = taken;
  late.sequence = 6;
  SendDatagram(socket.port(), late);  // by the source: out of order
  cycle(kNow);

  ASSERT_EQ(heard.size(), 1u) << "only the sample the source took is on the bus";
  EXPECT_EQ(heard[0].session_id, kSession);
  EXPECT_EQ(heard[0].utime, kNow);
  EXPECT_EQ(heard[0].seq, 7);
  const ParsedVehiclePacket back = ReadVehicleMessage(heard[0]);
  ASSERT_TRUE(back.packet) << back.error;
  EXPECT_EQ(back.packet->specific_force_m_s2, taken.specific_force_m_s2);
  EXPECT_EQ(back.packet->angular_velocity_rad_s, taken.angular_velocity_rad_s);
  EXPECT_EQ(back.packet->command, CueCommand::kEngage);
}

}  // namespace
}  // namespace edsp
