// GroupFileEditor: every shipped group file, loaded and written back
// unchanged, is the same group to edsp-launch and the same routes to the
// nodes; each edit changes what it says and nothing else; a member the file
// does not have is named.
#include "group_file_editor.h"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/node/group_file.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

std::string Shipped(const std::string& group) { return SourcePath("deploy/groups/") + group + ".toml"; }

std::string Scratch(const std::string& name) { return test_support::ScratchDir("group_file_editor") + "/" + name; }

void ExpectSameMembers(const GroupSpec& a, const GroupSpec& b) {
  ASSERT_EQ(a.members.size(), b.members.size());
  for (std::size_t i = 0; i < a.members.size(); ++i) {
    const MemberSpec &x = a.members[i], &y = b.members[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.command, y.command) << x.name;
    EXPECT_EQ(x.args, y.args) << x.name;
    EXPECT_EQ(x.env, y.env) << x.name;
    EXPECT_EQ(x.host, y.host) << x.name;
    EXPECT_EQ(x.restart, y.restart) << x.name;
    EXPECT_EQ(x.max_restarts, y.max_restarts) << x.name;
    EXPECT_EQ(x.start_delay_ms, y.start_delay_ms) << x.name;
    EXPECT_EQ(x.node_options, y.node_options) << x.name;
    EXPECT_EQ(x.realtime_priority, y.realtime_priority) << x.name;
    EXPECT_EQ(x.cpus, y.cpus) << x.name;
    EXPECT_EQ(x.requires_members, y.requires_members) << x.name;
  }
}

class ShippedGroup : public testing::TestWithParam<std::string> {};

TEST_P(ShippedGroup, WrittenBackUnchangedItIsTheSameGroupAndTheSameRoutes) {
  ::setenv("EDSP_REPLAY_LOG", "run.lcmlog", 0);  // the replay group has no default for it
  const std::string original = Shipped(GetParam()), copy = Scratch(GetParam() + ".toml");
  const GroupSpec written = GroupFileEditor::Load(original).Write(copy);
  const GroupSpec shipped = LoadGroupFile(original);
  EXPECT_EQ(written.name, shipped.name);
  EXPECT_EQ(written.config, shipped.config);
  EXPECT_EQ(written.session_id, shipped.session_id);
  EXPECT_EQ(written.MemberHosts(), shipped.MemberHosts());
  EXPECT_EQ(written.hosts.size(), shipped.hosts.size());
  ExpectSameMembers(written, shipped);
  const TransportConfig a = LoadTransportConfig(copy), b = LoadTransportConfig(original);
  EXPECT_EQ(a.lcm_url, b.lcm_url);
  EXPECT_EQ(a.shm_prefix, b.shm_prefix);
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (const auto& [channel, route] : b.channels) {
    const ChannelRoute& other = a.channels.at(channel);
    EXPECT_EQ(other.path, route.path) << channel;
    EXPECT_EQ(other.mirror_every, route.mirror_every) << channel;
    EXPECT_EQ(other.slots, route.slots) << channel;
    EXPECT_EQ(other.writer, route.writer) << channel;
  }
}

INSTANTIATE_TEST_SUITE_P(DeployGroups, ShippedGroup,
                         testing::Values("sim", "sim-web", "sim-modbus", "sim-cia402", "demo", "calibrate", "replay",
                                         "multihost"));

TEST(GroupFileEditor, EachEditChangesWhatItSaysAndNothingElse) {
  GroupFileEditor g = GroupFileEditor::Load(Shipped("sim"));
  g.SetGroup("name", "t1")
      .SetGroup("session_id", 77)
      .SetTransport("shm_prefix", "edsp.t1")
      .SetChannel("EDSP_LEG_COMMAND", "path", "both")
      .SetChannel("EDSP_LEG_COMMAND", "mirror_every", 10)
      .SetArg("kinematics", "--pr-mode", "none")  // replaces the value after the flag
      .SetArg("kinematics", "--stale-ms", "250")  // appends flag and value
      .SetArg("actuator_bridge", "--stale-ms", "50")
      .RemoveArg("actuator_bridge", "--stale-ms")  // both go
      .AppendArgs("logger", {"--flush-ms", "50"})
      .ReplaceArgs("planner", {"--motions", "Lz"})
      .SetMember("rig", "start_delay_ms", 500)
      .SetMemberList("rig", "cpus", std::vector<std::int64_t>{0})
      .InsertMember("rig", "drive_sim", "edsp-drive-sim", {"--axes", "rig"})
      .RemoveMember("logger");
  const std::string path = Scratch("edited.toml");
  const GroupSpec spec = g.Write(path);
  const GroupSpec shipped = LoadGroupFile(Shipped("sim"));
  EXPECT_EQ(spec.name, "t1");
  EXPECT_EQ(spec.session_id, 77);
  std::vector<std::string> names;
  for (const MemberSpec& m : spec.members) names.push_back(m.name);
  EXPECT_EQ(names, (std::vector<std::string>{"rig", "drive_sim", "actuator_bridge", "kinematics", "planner"}));
  auto member = [&](const GroupSpec& s, const std::string& name) {
    for (const MemberSpec& m : s.members) {
      if (m.name == name) return m;
    }
    throw std::runtime_error("no " + name);
  };
  EXPECT_EQ(member(spec, "kinematics").args, (std::vector<std::string>{"--pr-mode", "none", "--stale-ms", "250"}));
  EXPECT_EQ(member(spec, "planner").args, (std::vector<std::string>{"--motions", "Lz"}));
  EXPECT_EQ(member(spec, "actuator_bridge").args, member(shipped, "actuator_bridge").args);
  EXPECT_EQ(member(spec, "rig").start_delay_ms, 500);
  EXPECT_EQ(member(spec, "rig").cpus, (std::vector<int>{0}));
  EXPECT_EQ(member(spec, "rig").args, member(shipped, "rig").args);  // untouched
  EXPECT_EQ(member(spec, "drive_sim").args, (std::vector<std::string>{"--axes", "rig"}));
  EXPECT_EQ(member(spec, "actuator_bridge").start_delay_ms, member(shipped, "actuator_bridge").start_delay_ms);
  const TransportConfig t = LoadTransportConfig(path);
  EXPECT_EQ(t.shm_prefix, "edsp.t1");
  EXPECT_EQ(t.Route("EDSP_LEG_COMMAND").path, ChannelPath::kBoth);
  EXPECT_EQ(t.Route("EDSP_LEG_COMMAND").mirror_every, 10u);
}

TEST(GroupFileEditor, AMemberTheFileDoesNotHaveIsNamed) {
  GroupFileEditor g = GroupFileEditor::Load(Shipped("sim"));
  try {
    g.SetArg("drive_sim", "--axes", "rig");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sim.toml: no member \"drive_sim\""), std::string::npos) << e.what();
  }
  EXPECT_THROW(GroupFileEditor::Load(Scratch("missing.toml")), std::runtime_error);
}

TEST(GroupFileEditor, AnEditTheLauncherWouldRefuseIsRefusedAtWrite) {
  GroupFileEditor g = GroupFileEditor::Load(Shipped("sim"));
  g.SetMember("rig", "restart", "sometimes");
  EXPECT_THROW(g.Write(Scratch("refused.toml")), std::runtime_error);
}

// A flag that ends the list without its value gets the value, not a
// second flag.
TEST(GroupFileEditor, AFlagThatEndsTheListGetsItsValue) {
  GroupFileEditor g = GroupFileEditor::Load(Shipped("sim"));
  g.ReplaceArgs("planner", {"--motions"}).SetArg("planner", "--motions", "Lz");
  EXPECT_EQ(g.Args("planner"), (std::vector<std::string>{"--motions", "Lz"}));
  g.ReplaceArgs("planner", {"--csv", "a.csv", "--dry-run"}).RemoveArg("planner", "--dry-run");
  EXPECT_EQ(g.Args("planner"), (std::vector<std::string>{"--csv", "a.csv"}));
}

TEST(ParseArgList, TomlItemsBecomeArguments) {
  EXPECT_EQ(ParseArgList(R"("--motions", "Lz,Rz", "--stops", "3")"),
            (std::vector<std::string>{"--motions", "Lz,Rz", "--stops", "3"}));
  EXPECT_TRUE(ParseArgList("").empty());
  EXPECT_THROW(ParseArgList(R"("--stops", 3)"), std::invalid_argument);
  EXPECT_THROW(ParseArgList(R"("unclosed)"), std::invalid_argument);
}

}  // namespace
}  // namespace edsp
