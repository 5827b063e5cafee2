// The channel table (channels.h) against what it must agree with: the
// message types (message_types.h, lcmtypes/CMakeLists.txt) and the contract
// users read (docs/interfaces.md §1). Each is parsed here on its own, so a
// channel or a type added in one place and not the others fails.
#include <gtest/gtest.h>

#include <cctype>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "edsp/channels.h"
#include "edsp/message_types.h"
#include "edsp/node/build_paths.h"
#include "edsp/setpoint_phases.h"

namespace edsp {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_FALSE(text.str().empty()) << path << " is empty or missing";
  return text.str();
}

std::set<std::string> MessageTypeNames() {
  std::set<std::string> names;
  ForEachMessageType([&](auto tag) { names.insert(decltype(tag)::type::getTypeName()); });
  return names;
}

TEST(ChannelTable, EveryChannelCarriesAKnownTypeAndEveryTypeHasAChannel) {
  const std::set<std::string> types = MessageTypeNames();
  EXPECT_EQ(types.size(), kMessageTypeCount) << "a type listed twice";
  std::set<std::string> carried, names;
  for (const channel::Channel& c : channel::kChannels) {
    EXPECT_EQ(types.count(std::string(c.type)), 1u) << c.name << ": " << c.type << " is not in message_types.h";
    EXPECT_TRUE(names.insert(std::string(c.name)).second) << c.name << " listed twice";
    EXPECT_EQ(c.name.rfind("EDSP_", 0), 0u) << c.name;
    EXPECT_GE(c.rate_hz, 0.0) << c.name;
    carried.insert(std::string(c.type));
  }
  EXPECT_EQ(carried, types) << "a message type no channel carries";
}

TEST(ChannelTable, TheMessageTypesAreTheOnesLcmGenBuilds) {
  const std::string cmake = Slurp(SourcePath("lcmtypes/CMakeLists.txt"));
  std::smatch list;
  ASSERT_TRUE(std::regex_search(cmake, list, std::regex(R"(set\(EDSP_LCM_TYPES([^)]*)\))")));
  std::set<std::string> built;
  std::istringstream words(list[1].str());
  for (std::string word; words >> word;) built.insert(word);
  EXPECT_EQ(built, MessageTypeNames());
}

// The older layouts a log may hold: built from lcmtypes/legacy/, and each
// the older layout of a type still carried (its name and "_v1").
TEST(ChannelTable, TheLegacyTypesAreTheOnesLcmGenBuildsAndEachIsAnOlderCarriedType) {
  const std::string cmake = Slurp(SourcePath("lcmtypes/CMakeLists.txt"));
  std::smatch list;
  ASSERT_TRUE(std::regex_search(cmake, list, std::regex(R"(set\(EDSP_LCM_LEGACY_TYPES([^)]*)\))")));
  std::set<std::string> built, legacy;
  std::istringstream words(list[1].str());
  for (std::string word; words >> word;) built.insert(word);
  detail::ForEachMessageType<LegacyMessageTypes>([&](auto tag) { legacy.insert(decltype(tag)::type::getTypeName()); },
                                                 std::make_index_sequence<std::tuple_size_v<LegacyMessageTypes>>{});
  EXPECT_EQ(built, legacy);
  const std::set<std::string> types = MessageTypeNames();
  for (const std::string& old : legacy) {
    const std::string today = old.substr(0, old.rfind("_v1_t")) + "_t";
    EXPECT_EQ(types.count(today), 1u) << old << ": no " << today << " is carried";
  }
}

TEST(ChannelTable, InterfacesMdListsEveryChannelWithItsType) {
  const std::string doc = Slurp(SourcePath("docs/interfaces.md"));
  const std::regex row(R"(\n\| `(EDSP_[A-Z_]+)` \| `([a-z_]+_t)` \|)");
  std::map<std::string, std::string> documented;
  for (auto it = std::sregex_iterator(doc.begin(), doc.end(), row); it != std::sregex_iterator(); ++it) {
    documented[(*it)[1].str()] = (*it)[2].str();
  }
  std::map<std::string, std::string> table;
  for (const channel::Channel& c : channel::kChannels) table[std::string(c.name)] = std::string(c.type);
  EXPECT_EQ(documented, table);
}

TEST(ChannelTable, OnlyStatusFaultsRequestsAndTheirRepliesInterleaveSeveralSeqStreams) {
  std::set<std::string> many;
  for (const channel::Channel& c : channel::kChannels) {
    if (channel::HasManyPublishers(c.name)) many.insert(std::string(c.name));
  }
  EXPECT_EQ(many, (std::set<std::string>{"EDSP_STATUS", "EDSP_FAULT", "EDSP_ARM", "EDSP_PR_MODE", "EDSP_CALIBRATION",
                                         "EDSP_REPLY", "EDSP_MOTION_REQUEST"}));
  EXPECT_FALSE(channel::HasManyPublishers("OTHER_APP"));
  // Their gaps, and the vehicle's numbering's, are no bus's losses; one publisher's are.
  EXPECT_TRUE(channel::SeqGapsAreNotLosses("EDSP_FAULT"));
  EXPECT_TRUE(channel::SeqGapsAreNotLosses("EDSP_VEHICLE"));
  EXPECT_FALSE(channel::HasManyPublishers("EDSP_VEHICLE"));
  EXPECT_FALSE(channel::SeqGapsAreNotLosses("EDSP_SETPOINT"));
  EXPECT_FALSE(channel::SeqGapsAreNotLosses("OTHER_APP"));
  EXPECT_EQ(channel::Find("EDSP_NOPE"), nullptr);
  static_assert(channel::Find(channel::kLegCommand)->rate_hz == 1000.0, "usable at compile time");
}

// The phase table (setpoint_phases.h) names every PHASE_* constant of
// pose_setpoint_t.lcm, read from the file: a phase added there and not
// here would reach Python and the readers nameless.
TEST(SetpointPhases, TheTableNamesEveryPhaseOfTheLcmFile) {
  const std::string lcm = Slurp(SourcePath("lcmtypes/pose_setpoint_t.lcm"));
  const std::regex constant(R"(const int8_t PHASE_(\w+) = (\d+);)");
  std::map<int, std::string> in_file;
  for (std::sregex_iterator m(lcm.begin(), lcm.end(), constant), end; m != end; ++m) {
    std::string name = (*m)[1];
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    in_file[std::stoi((*m)[2])] = name;
  }
  std::map<int, std::string> in_table;
  for (const SetpointPhaseRow& row : kSetpointPhases) in_table[row.phase] = std::string(row.name);
  EXPECT_EQ(in_table, in_file);
  EXPECT_EQ(in_file.size(), 4u);
}

}  // namespace
}  // namespace edsp
