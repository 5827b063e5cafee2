// Group files: ${NAME} / ${NAME:-default} in member args, errors that name
// the file, line and what is wrong, and one parser for the launcher and the
// members.
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "edsp/transport/host_routes.h"
#include "group_file.h"
#include "systemd_units.h"
#include "scratch_dir.h"
#include "thrown_message.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

const char* Lookup(const std::string& name) {
  static const std::map<std::string, std::string> env = {{"MODE", "none"}, {"EMPTY", ""}};
  const auto it = env.find(name);
  return it == env.end() ? nullptr : it->second.c_str();
}

TEST(ExpandVariables, SetUnsetDefaultsAndPlainText) {
  EXPECT_EQ(ExpandVariables("--pr-mode", Lookup), "--pr-mode");
  EXPECT_EQ(ExpandVariables("${MODE}", Lookup), "none");
  EXPECT_EQ(ExpandVariables("${MODE:-signed}", Lookup), "none");
  EXPECT_EQ(ExpandVariables("${UNSET:-signed}", Lookup), "signed");
  EXPECT_EQ(ExpandVariables("${EMPTY:-x}", Lookup), "x");  // empty counts as unset, as in sh
  EXPECT_EQ(ExpandVariables("a${MODE}b${UNSET:-}c", Lookup), "anonebc");
  EXPECT_EQ(ExpandVariables("cost $5", Lookup), "cost $5");
}

TEST(ExpandVariables, ErrorsNameTheVariable) {
  auto message = [](const std::string& text) {
    try {
      ExpandVariables(text, Lookup);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("${UNSET}").find("${UNSET} is not set"), std::string::npos);
  EXPECT_NE(message("x${MODE").find("unclosed"), std::string::npos);
  EXPECT_NE(message("${1A}").find("bad variable name"), std::string::npos);
  EXPECT_NE(message("${}").find("bad variable name"), std::string::npos);
}

TEST(LoadGroupFile, ExpandsArgsFromTheEnvironmentAndNamesTheLine) {
  const std::string path = test_support::ScratchRoot() + "/group_file_test.toml";
  std::ofstream(path) << "[group]\nname = \"t\"\n[[member]]\nname = \"k\"\ncommand = \"edsp-kinematics\"\n"
                         "args = [\"--pr-mode\", \"${EDSP_TEST_MODE:-signed}\",\n"
                         "        \"${EDSP_TEST_REQUIRED}\"]\n";
  ::unsetenv("EDSP_TEST_MODE");
  ::setenv("EDSP_TEST_REQUIRED", "--replay", 1);
  GroupSpec g = LoadGroupFile(path);
  ASSERT_EQ(g.members.size(), 1u);
  EXPECT_EQ(g.members[0].args, (std::vector<std::string>{"--pr-mode", "signed", "--replay"}));
  ::setenv("EDSP_TEST_MODE", "unsigned", 1);
  EXPECT_EQ(LoadGroupFile(path).members[0].args[1], "unsigned");
  ::unsetenv("EDSP_TEST_REQUIRED");
  try {
    LoadGroupFile(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":7:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("EDSP_TEST_REQUIRED"), std::string::npos) << e.what();
  }
  ::unlink(path.c_str());
}

TEST(LoadGroupFile, BadValuesAreNamed) {
  const std::string path = test_support::ScratchRoot() + "/group_file_bad.toml";
  std::ofstream(path) << "[[member]]\nname = \"k\"\ncommand = \"x\"\nrestart = \"sometimes\"\n";
  try {
    LoadGroupFile(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sometimes"), std::string::npos) << e.what();
  }
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace edsp

namespace edsp {
namespace {

TEST(LoadGroupFile, RealTimePriorityAndCpusAreReadAndChecked) {
  const std::string path = test_support::ScratchRoot() + "/group_file_rt.toml";
  std::ofstream(path) << "[[member]]\nname = \"k\"\ncommand = \"x\"\nrealtime_priority = 80\ncpus = [1, 3]\n";
  const GroupSpec g = LoadGroupFile(path);
  EXPECT_EQ(g.members[0].realtime_priority, 80);
  EXPECT_EQ(g.members[0].cpus, (std::vector<int>{1, 3}));
  for (const char* bad :
       {"realtime_priority = 100", "realtime_priority = -1", "cpus = [\"one\"]", "cpus = 1", "cpus = [5000]"}) {
    std::ofstream(path) << "[[member]]\nname = \"k\"\ncommand = \"x\"\n" << bad << "\n";
    try {
      LoadGroupFile(path);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
    }
  }
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace edsp

// Groups spanning hosts: what every host's launcher must agree on, and the
// systemd units of one host.
namespace edsp {
namespace {

std::string ErrorLoading(const std::string& text) {
  const std::string path = test_support::ScratchRoot() + "/group_file_hosts.toml";
  std::ofstream(path) << text;
  std::string error = "no error";
  try {
    LoadGroupFile(path);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  ::unlink(path.c_str());
  return error;
}

constexpr const char* kTwoHostMembers =
    "[[member]]\nname = \"rig\"\ncommand = \"edsp-rig\"\nhost = \"drive\"\n"
    "[[member]]\nname = \"bridge\"\ncommand = \"edsp-actuator-bridge\"\nhost = \"drive\"\nrequires = [\"rig\"]\n"
    "restart = \"always\"\nstart_delay_ms = 100\n"
    "[[member]]\nname = \"kinematics\"\ncommand = \"edsp-kinematics\"\nhost = \"controller\"\n";
constexpr const char* kTtl1 = "[transport]\nlcm_url = \"udpm://239.255.76.67:7667?ttl=1\"\n";

TEST(LoadGroupFile, AGroupSpanningHostsNeedsASessionAndTtl) {
  EXPECT_NE(ErrorLoading(std::string(kTtl1) + kTwoHostMembers)
                .find("spans hosts (controller, drive): set [group] session_id"),
            std::string::npos);
  EXPECT_NE(ErrorLoading(std::string("[group]\nsession_id = 7\n") + kTwoHostMembers).find("ttl=0"), std::string::npos);
  EXPECT_EQ(ErrorLoading(std::string("[group]\nsession_id = 7\n") + kTtl1 + kTwoHostMembers), "no error");
}

TEST(LoadGroupFile, RequiresAndHostsAreChecked) {
  const std::string head = std::string("[group]\nsession_id = 7\n") + kTtl1;
  EXPECT_NE(
      ErrorLoading(head + kTwoHostMembers + "requires = [\"rig\"]\n").find("systemd orders units of one host only"),
      std::string::npos);
  EXPECT_NE(
      ErrorLoading(head + kTwoHostMembers + "requires = [\"rgi\"]\n").find("requires \"rgi\", which is no member"),
      std::string::npos);
  EXPECT_NE(ErrorLoading(head + "[hosts.drive]\ninterface = \"eth0\"\n" + kTwoHostMembers)
                .find("kinematics is on host controller, which [hosts] does not list"),
            std::string::npos);
  EXPECT_NE(
      ErrorLoading(head + "[hosts.drive]\nnic = \"eth0\"\n" + kTwoHostMembers).find("unknown key [hosts.drive] nic"),
      std::string::npos);
}

TEST(MemberUnits, OneHostsMembersInStartOrderWithTheirPolicies) {
  const std::string path = test_support::ScratchRoot() + "/group_units.toml";
  std::ofstream(path) << "[group]\nname = \"mh\"\nsession_id = 7\n" << kTtl1 << kTwoHostMembers;
  const GroupSpec group = LoadGroupFile(path);
  const std::vector<UnitFile> units = MemberUnits(group, "drive", "/opt/edsp", "/opt/edsp/build/bin");
  ASSERT_EQ(units.size(), 3u);  // rig, bridge, the target
  EXPECT_EQ(units[0].path, "edsp@mh.rig.service.d/10-edsp-member.conf");
  EXPECT_EQ(units[0].text.find("After=edsp@"), std::string::npos);  // first on this host
  EXPECT_NE(units[0].text.find("Restart=on-failure"), std::string::npos);
  EXPECT_NE(units[0].text.find("EDSP_GROUP_FILE=" + path + " EDSP_MEMBER=rig"), std::string::npos);
  EXPECT_NE(units[1].text.find("After=edsp@mh.rig.service"), std::string::npos);
  EXPECT_NE(units[1].text.find("Requires=edsp@mh.rig.service"), std::string::npos);
  EXPECT_NE(units[1].text.find("Restart=always"), std::string::npos);
  EXPECT_NE(units[1].text.find("ExecStartPost=/bin/sleep 0.100"), std::string::npos);
  EXPECT_EQ(units[2].path, "edsp-mh.target");
  EXPECT_NE(units[2].text.find("Wants=edsp@mh.rig.service edsp@mh.bridge.service\n"), std::string::npos);
  EXPECT_EQ(units[2].text.find("kinematics"), std::string::npos);  // another host's
  EXPECT_THROW(MemberUnits(group, "operator", "/opt/edsp", "/opt/edsp/build/bin"), std::runtime_error);
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace edsp

// One parser for the launcher and the members: what a member reads of the
// group file (its routes, LoadTransportConfig) is what the launcher read,
// and a malformed member is one error, the same whoever reads the file.
namespace edsp {
namespace {

std::string ShippedGroupFile(const std::string& name) { return SourcePath("deploy/groups/") + name + ".toml"; }

std::string WriteScratch(const std::string& name, const std::string& text) {
  const std::string path = test_support::ScratchRoot() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(GroupFile, MembersTakeTheRoutesTheLauncherReadWithEachMembersHost) {
  const std::string path = ShippedGroupFile("multihost");
  const TransportConfig members = LoadTransportConfig(path);  // as a member reads it: no launcher environment
  const GroupSpec launcher = LoadGroupFile(path);
  const HostAssignment hosts = {{"rig", "drive"},
                                {"actuator_bridge", "drive"},
                                {"kinematics", "controller"},
                                {"logger", "operator"},
                                {"planner", "operator"}};
  EXPECT_EQ(members.member_hosts, hosts);
  EXPECT_EQ(launcher.transport.member_hosts, hosts);
  EXPECT_EQ(members.lcm_url, launcher.transport.lcm_url);
  EXPECT_EQ(members.shm_prefix, "edsp.multihost");
  ASSERT_EQ(members.channels.size(), launcher.transport.channels.size());
  for (const auto& [channel, route] : launcher.transport.channels) {
    EXPECT_EQ(members.Route(channel).path, route.path) << channel;
    EXPECT_EQ(members.Route(channel).writer, route.writer) << channel;
  }
  // The hosts route as they did: the writer also puts every message on LCM,
  // a reader on another host reads LCM.
  EXPECT_EQ(RoutesForMember(members, "kinematics").Route("EDSP_LEG_COMMAND").path, ChannelPath::kBoth);
  EXPECT_EQ(RoutesForMember(members, "actuator_bridge").Route("EDSP_LEG_COMMAND").path, ChannelPath::kLcm);
  EXPECT_EQ(RoutesForMember(members, "actuator_bridge").Route("EDSP_LEG_STATE").path, ChannelPath::kBoth);
  // A one-host group: every member "local", routes as written.
  const TransportConfig sim = LoadTransportConfig(ShippedGroupFile("sim"));
  for (const MemberSpec& m : LoadGroupFile(ShippedGroupFile("sim")).members) {
    EXPECT_EQ(sim.member_hosts.at(m.name), "local") << m.name;
  }
  EXPECT_EQ(GroupHosts(sim), std::vector<std::string>{"local"});
}

TEST(GroupFile, AMalformedMemberIsOneErrorNamingFileLineAndKeyWhoeverReads) {
  const std::string path = WriteScratch("group_file_one_parser.toml",
                                        "[[member]]\nname = \"rig\"\ncommand = \"edsp-rig\"\n"
                                        "[[member]]\nname = \"kinematics\"\ncommand = \"edsp-kinematics\"\nhost = 5\n");
  const std::string for_members = test_support::ThrownMessage<std::runtime_error>([&] { LoadTransportConfig(path); });
  const std::string for_launcher = test_support::ThrownMessage<std::runtime_error>([&] { LoadGroupFile(path); });
  EXPECT_NE(for_members.find(path + ":7: [[member]] #2 host must be a string"), std::string::npos) << for_members;
  EXPECT_EQ(for_members, for_launcher);
  // A member without a name was skipped by a routes-only reader once; now it
  // is refused by everyone.
  std::ofstream(path) << "[[member]]\ncommand = \"edsp-rig\"\nhost = \"drive\"\n";
  EXPECT_NE(test_support::ThrownMessage<std::runtime_error>([&] {
              LoadTransportConfig(path);
            }).find("[[member]] #1 needs a name and a command"),
            std::string::npos);
  ::unlink(path.c_str());
  EXPECT_EQ(test_support::ThrownMessage<std::runtime_error>([&] { LoadTransportConfig(path); }),
            path + ": cannot open file");
}

TEST(GroupFile, ADisabledMemberIsCheckedButNotStarted) {
  const std::string path = WriteScratch("group_file_enabled.toml",
                                        "[[member]]\nname = \"rig\"\ncommand = \"edsp-rig\"\n"
                                        "[[member]]\nname = \"web\"\ncommand = \"edsp-web\"\nenabled = false\n");
  const GroupSpec group = LoadGroupFile(path);
  ASSERT_EQ(group.members.size(), 1u);
  EXPECT_EQ(group.members[0].name, "rig");
  // Still read as any member: an error in it is an error.
  std::ofstream(path) << "[[member]]\nname = \"web\"\ncommand = \"edsp-web\"\nenabled = false\nhost = 5\n";
  EXPECT_NE(test_support::ThrownMessage<std::runtime_error>([&] { LoadGroupFile(path); }).find(":5:"),
            std::string::npos);
  std::ofstream(path) << "[[member]]\nname = \"web\"\ncommand = \"edsp-web\"\nenabled = \"no\"\n";
  EXPECT_NE(test_support::ThrownMessage<std::runtime_error>([&] { LoadGroupFile(path); }).find(":4:"),
            std::string::npos);
  // The shipped sim group carries the panel, off.
  for (const MemberSpec& m : LoadGroupFile(ShippedGroupFile("sim")).members) EXPECT_NE(m.name, "web");
  bool web = false;
  for (const MemberSpec& m : LoadGroupFile(ShippedGroupFile("sim-web")).members) web = web || m.name == "web";
  EXPECT_TRUE(web);
  ::unlink(path.c_str());
}

TEST(GroupFile, MembersKeepArgsAsWrittenOnlyTheLauncherExpandsThem) {
  const std::string path =
      WriteScratch("group_file_args.toml",
                   "[[member]]\nname = \"k\"\ncommand = \"edsp-kinematics\"\nargs = [\"${EDSP_TEST_UNSET}\"]\n");
  ::unsetenv("EDSP_TEST_UNSET");
  EXPECT_EQ(ReadGroupFile(path).members[0].args, std::vector<std::string>{"${EDSP_TEST_UNSET}"});
  EXPECT_NO_THROW(LoadTransportConfig(path));
  EXPECT_NE(test_support::ThrownMessage<std::runtime_error>([&] {
              LoadGroupFile(path);
            }).find(path + ":4: [[member]] #1 args: ${EDSP_TEST_UNSET} is not set"),
            std::string::npos);
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace edsp
