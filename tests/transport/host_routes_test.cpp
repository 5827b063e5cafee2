// A group spanning hosts: shared memory only between members of one host,
// LCM between hosts, decided from the group file; and the checks that keep
// a multi-host group from starting with a host-only LCM or an unowned segment.
// The members' hosts come as the group file's parser hands them over
// (HostAssignment): transport reads no [[member]] itself.
#include <gtest/gtest.h>

#include "thrown_message.h"

#include "edsp/config_file/config_error.h"
#include "edsp/transport/error.h"
#include "edsp/transport/host_routes.h"

namespace edsp {
namespace {

// operator: planner + logger; controller: kinematics; drive: bridge + rig.
const HostAssignment kThreeHosts = {{"planner", "operator"},
                                    {"logger", "operator"},
                                    {"kinematics", "controller"},
                                    {"rig", "drive"},
                                    {"actuator_bridge", "drive"}};

std::string ThreeHosts(const std::string& url, const std::string& command_route) {
  return R"([transport]
lcm_url = ")" +
         url + R"("
[transport.channels.EDSP_LEG_COMMAND]
)" + command_route +
         R"(
[transport.channels.EDSP_RIG_TRUTH]
path = "shm"
writer = "rig"
readers = ["actuator_bridge"]
)";
}

constexpr const char* kTtl1 = "udpm://239.255.76.67:7667?ttl=1";

TransportConfig OnThreeHosts(const std::string& text) { return ParseTransportConfig(text, "g.toml", kThreeHosts); }

std::string ErrorOf(const std::string& text) {
  return test_support::ThrownMessage<TransportError>([&] { OnThreeHosts(text); }, "no error");
}

// A value of the wrong type is the file's error, not the routes'.
std::string FileErrorOf(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { OnThreeHosts(text); }, "no error");
}

TEST(HostRoutes, WriterPublishesBothWhenAReaderIsElsewhereAndRemoteReadersUseLcm) {
  const TransportConfig group = OnThreeHosts(ThreeHosts(kTtl1, "path = \"shm\"\nwriter = \"kinematics\""));
  EXPECT_EQ(GroupHosts(group), (std::vector<std::string>{"controller", "drive", "operator"}));
  const ChannelRoute writer = RoutesForMember(group, "kinematics").Route("EDSP_LEG_COMMAND");
  EXPECT_EQ(writer.path, ChannelPath::kBoth);
  EXPECT_EQ(writer.mirror_every, 1u);  // every message crosses, not a decimated mirror
  EXPECT_EQ(RoutesForMember(group, "actuator_bridge").Route("EDSP_LEG_COMMAND").path, ChannelPath::kLcm);
  EXPECT_EQ(RoutesForMember(group, "logger").Route("EDSP_LEG_COMMAND").path, ChannelPath::kLcm);
  // A program that is no member (edsp-ctl, a spy) cannot know the writer is local.
  EXPECT_EQ(RoutesForMember(group, "").Route("EDSP_LEG_COMMAND").path, ChannelPath::kLcm);
}

TEST(HostRoutes, ReadersAllOnTheWritersHostKeepSharedMemoryOnly) {
  const TransportConfig group = OnThreeHosts(ThreeHosts(kTtl1, "path = \"lcm\""));
  EXPECT_EQ(RoutesForMember(group, "rig").Route("EDSP_RIG_TRUTH").path, ChannelPath::kShm);
  EXPECT_EQ(RoutesForMember(group, "actuator_bridge").Route("EDSP_RIG_TRUTH").path, ChannelPath::kShm);
  EXPECT_EQ(RoutesForMember(group, "logger").Route("EDSP_RIG_TRUTH").path, ChannelPath::kLcm);
  EXPECT_EQ(RoutesForMember(group, "kinematics").Route("EDSP_LEG_COMMAND").path, ChannelPath::kLcm);
}

TEST(HostRoutes, SameHostReaderOfAMirroredChannelKeepsReadingSharedMemory) {
  std::string text = ThreeHosts(kTtl1, "path = \"both\"\nmirror_every = 10\nwriter = \"actuator_bridge\"");
  const TransportConfig group = OnThreeHosts(text);
  EXPECT_EQ(RoutesForMember(group, "rig").Route("EDSP_LEG_COMMAND").path, ChannelPath::kBoth);
  const ChannelRoute writer = RoutesForMember(group, "actuator_bridge").Route("EDSP_LEG_COMMAND");
  EXPECT_EQ(writer.path, ChannelPath::kBoth);
  EXPECT_EQ(writer.mirror_every, 1u);
}

TEST(HostRoutes, OneHostGroupsAreUnchanged) {
  const TransportConfig group = ParseTransportConfig(R"([transport]
[transport.channels.EDSP_LEG_COMMAND]
path = "both"
mirror_every = 10
)",
                                                     "g.toml", {{"kinematics", "local"}, {"actuator_bridge", "local"}});
  EXPECT_EQ(GroupHosts(group), (std::vector<std::string>{"local"}));
  for (const char* member : {"kinematics", "actuator_bridge", ""}) {
    const ChannelRoute route = RoutesForMember(group, member).Route("EDSP_LEG_COMMAND");
    EXPECT_EQ(route.path, ChannelPath::kBoth) << member;
    EXPECT_EQ(route.mirror_every, 10u) << member;
  }
}

TEST(HostRoutes, MultiHostNeedsTtlAtLeastOne) {
  const std::string error = ErrorOf(ThreeHosts("udpm://239.255.76.67:7667?ttl=0", "path = \"lcm\""));
  EXPECT_NE(error.find("g.toml"), std::string::npos) << error;
  EXPECT_NE(error.find("ttl=0"), std::string::npos) << error;
  EXPECT_NE(error.find("3 hosts (controller, drive, operator)"), std::string::npos) << error;
  EXPECT_NE(error.find("set ttl=1"), std::string::npos) << error;
  // LCM's default ttl (no option) is 0 as well.
  EXPECT_NE(ErrorOf(ThreeHosts("udpm://239.255.76.67:7667", "path = \"lcm\"")).find("ttl=0"), std::string::npos);
}

TEST(HostRoutes, SharedMemoryChannelsOfAMultiHostGroupNameAKnownWriter) {
  EXPECT_NE(ErrorOf(ThreeHosts(kTtl1, "path = \"shm\"")).find("[transport.channels.EDSP_LEG_COMMAND] path = \"shm\""),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(ThreeHosts(kTtl1, "path = \"shm\"\nwriter = \"kinematic\"")).find("writer = \"kinematic\" is no member"),
      std::string::npos);
  EXPECT_NE(ErrorOf(ThreeHosts(kTtl1, "path = \"shm\"\nwriter = \"kinematics\"\nreaders = [\"bridge\"]"))
                .find("readers: \"bridge\" is no member"),
            std::string::npos);
  EXPECT_NE(FileErrorOf(ThreeHosts(kTtl1, "path = \"shm\"\nwriter = 3"))
                .find("[transport.channels.EDSP_LEG_COMMAND] writer must be a string"),
            std::string::npos);
}

// [[member]] tables in the text are not transport's to read: the hosts it
// routes for are the ones it is given, whatever the text says.
TEST(HostRoutes, HostsAreGivenNeverReadFromMemberTables) {
  const std::string members =
      "[[member]]\nname = \"kinematics\"\nhost = \"controller\"\n"
      "[[member]]\nname = \"actuator_bridge\"\nhost = \"drive\"\n";
  const std::string text = "[transport.channels.EDSP_LEG_COMMAND]\npath = \"shm\"\n" + members;
  const TransportConfig given_none = ParseTransportConfig(text, "g.toml", {});
  EXPECT_TRUE(given_none.member_hosts.empty());
  EXPECT_TRUE(GroupHosts(given_none).empty());
  // Given the two hosts, the same text is a group spanning hosts: ttl=0 and
  // a writerless shm channel are refused.
  const std::string error = test_support::ThrownMessage<TransportError>(
      [&] {
        ParseTransportConfig(text, "g.toml", {{"kinematics", "controller"}, {"actuator_bridge", "drive"}});
      },
      "no error");
  EXPECT_NE(error.find("2 hosts (controller, drive)"), std::string::npos) << error;
}

TEST(HostRoutes, TtlIsReadFromTheUrl) {
  EXPECT_EQ(LcmUrlTtl("udpm://239.255.76.67:7667"), 0);
  EXPECT_EQ(LcmUrlTtl("udpm://239.255.76.67:7667?ttl=1"), 1);
  EXPECT_EQ(LcmUrlTtl("udpm://239.255.76.67:7667?recv_buf_size=4194304&ttl=2"), 2);
  EXPECT_THROW(LcmUrlTtl("udpm://239.255.76.67:7667?ttl=x"), TransportError);
  EXPECT_THROW(LcmUrlTtl("udpm://239.255.76.67:7667?ttl=256"), TransportError);
}

}  // namespace
}  // namespace edsp
