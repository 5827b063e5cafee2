// ChannelPattern: the whole name, the pattern as a whole.
#include "edsp/transport/channel_pattern.h"

#include <gtest/gtest.h>

#include "edsp/transport/error.h"

namespace edsp {
namespace {

TEST(ChannelPattern, MatchesTheWholeNameWithTheAlternationAsAWhole) {
  const ChannelPattern pattern("EDSP_LEG_COMMAND|EDSP_FAULT");
  EXPECT_TRUE(pattern.Matches("EDSP_LEG_COMMAND"));
  EXPECT_TRUE(pattern.Matches("EDSP_FAULT"));
  EXPECT_FALSE(pattern.Matches("EDSP_LEG_COMMAND_X")) << "^A|B$ would take this";
  EXPECT_FALSE(pattern.Matches("X_EDSP_FAULT")) << "^A|B$ would take this";
  EXPECT_FALSE(pattern.Matches("EDSP_LEG_STATE"));
  EXPECT_EQ(pattern.ForLcm(), "(EDSP_LEG_COMMAND|EDSP_FAULT)");

  const ChannelPattern all("EDSP_.*");
  EXPECT_TRUE(all.Matches("EDSP_TRACKER"));
  EXPECT_FALSE(all.Matches("OTHER_EDSP_TRACKER"));
}

TEST(ChannelPattern, APatternThatIsNoRegexIsRefusedNamingIt) {
  try {
    ChannelPattern pattern("EDSP_(");
    FAIL() << "accepted EDSP_(";
  } catch (const TransportError& e) {
    EXPECT_NE(std::string(e.what()).find("'EDSP_('"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("POSIX extended regex"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace edsp
