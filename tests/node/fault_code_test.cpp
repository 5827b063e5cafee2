// Fault codes by name and number, as users name them on edsp-log's command
// line: every code round-trips through its name, and nothing else is one.
#include <string>

#include <gtest/gtest.h>

#include "edsp/node/fault.h"

namespace edsp {
namespace {

TEST(FaultCode, EveryCodeIsFoundByItsNameAndItsNumber) {
  int named = 0;
  for (int c = 1; c < 64; ++c) {
    const auto code = static_cast<FaultCode>(c);
    const std::string name = FaultCodeName(code);
    if (name == "unknown") continue;
    ++named;
    EXPECT_EQ(FaultCodeFromText(name), code) << name;
    EXPECT_EQ(FaultCodeFromText(std::to_string(c)), code) << c;
  }
  EXPECT_EQ(named, 16);
  EXPECT_EQ(FaultCodeFromText("drive_backend"), FaultCode::kBackend);
  EXPECT_EQ(FaultCodeFromText("out-of-stroke"), FaultCode::kOutOfStroke);
  EXPECT_EQ(FaultCodeFromText("latched"), FaultCode::kLatched);
}

TEST(FaultCode, NothingElseNamesACode) {
  for (const char* text : {"", "0", "17", "16x", "x16", "Latched", "unknown", "stale "}) {
    EXPECT_FALSE(FaultCodeFromText(text).has_value()) << '"' << text << '"';
  }
}

}  // namespace
}  // namespace edsp
