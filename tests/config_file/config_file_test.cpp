// The one config reader: every error names the file, the line, the section
// and the key; absent keys give their fallback; nested tables come by key,
// arrays of tables in file order; sections outlive their file.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "edsp/config_file/config_file.h"
#include "thrown_message.h"

namespace edsp {
namespace {

std::string ErrorOf(const std::string& text, void (*read)(const ConfigFile&)) {
  return test_support::ThrownMessage<ConfigError>([&] { read(ConfigFile::Parse(text, "rig.toml")); }, "no error");
}

TEST(ConfigFile, ValuesAreReadWithTheirTypesAndAbsentKeysGiveTheFallback) {
  const ConfigFile file = ConfigFile::Parse(
      "[drive]\nlead_m = 0.01\npr_sign = -1\nname = \"a\"\nhot = true\nlegs = [1, 2, 3, 4, 5, 6]\n"
      "rows = [[1, 2], [3, 4.5]]\nnames = [\"x\", \"y\"]\n",
      "rig.toml");
  const ConfigSection drive = file.Section("drive");
  EXPECT_TRUE(drive.present());
  EXPECT_EQ(drive.label(), "[drive]");
  EXPECT_DOUBLE_EQ(drive.Number("lead_m", 0.0), 0.01);
  EXPECT_DOUBLE_EQ(drive.Number("pr_sign", 0.0), -1.0);  // an integer is a number too
  EXPECT_EQ(drive.Integer("pr_sign", 0), -1);
  EXPECT_EQ(drive.String("name", ""), "a");
  EXPECT_TRUE(drive.Bool("hot", false));
  EXPECT_EQ(drive.Numbers("legs", 6), (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(drive.NumberOrNumbers("legs", 6, 0.0)[5], 6.0);
  EXPECT_EQ(drive.Rows("rows", 2, 2), (std::vector<std::vector<double>>{{1, 2}, {3, 4.5}}));
  EXPECT_EQ(drive.Strings("names"), (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(drive.ArrayLength("legs"), 6);
  EXPECT_EQ(drive.ArrayLength("lead_m"), -1);
  EXPECT_DOUBLE_EQ(drive.Number("gear_ratio", 7.0), 7.0);
  EXPECT_EQ(drive.NumberOrNumbers("absent", 3, 2.0), (std::vector<double>{2, 2, 2}));
  EXPECT_FALSE(file.Section("limits").present());
  EXPECT_DOUBLE_EQ(file.Section("limits").Number("leg_max_m", 2.45), 2.45);
}

TEST(ConfigFile, ErrorsNameTheFileLineSectionAndKey) {
  EXPECT_EQ(
      ErrorOf("[drive]\nlead_m = \"10mm\"\n", [](const ConfigFile& f) { f.Section("drive").Number("lead_m", 0); }),
      "rig.toml:2: [drive] lead_m must be a number");
  EXPECT_EQ(ErrorOf("[drive]\n\nlead_m = nan\n", [](const ConfigFile& f) { f.Section("drive").Number("lead_m", 0); }),
            "rig.toml:3: [drive] lead_m = nan must be finite");
  EXPECT_EQ(
      ErrorOf("[drive]\nlead = 1\n", [](const ConfigFile& f) { f.Section("drive").RejectUnknownKeys({"lead_m"}); }),
      "rig.toml:2: unknown key [drive] lead (known keys: lead_m)");
  EXPECT_EQ(ErrorOf("[m]\nn = 1.5\n", [](const ConfigFile& f) { f.Section("m").Integer("n", 0); }),
            "rig.toml:2: [m] n must be an integer");
  EXPECT_EQ(ErrorOf("[m]\nn = 100\n", [](const ConfigFile& f) { f.Section("m").Integer("n", 0, 0, 99); }),
            "rig.toml:2: [m] n must be an integer in 0..99");
  EXPECT_EQ(ErrorOf("[m]\nv = [1, 2]\n", [](const ConfigFile& f) { f.Section("m").Numbers("v", 3); }),
            "rig.toml:2: [m] v must be an array of 3 numbers");
  EXPECT_EQ(ErrorOf("[m]\nr = [[1, 2],\n     [3]]\n", [](const ConfigFile& f) { f.Section("m").Rows("r", 2, 2); }),
            "rig.toml:3: [m] r row 2 must be an array of 2 numbers");
  EXPECT_EQ(ErrorOf("m = 3\n", [](const ConfigFile& f) { f.Section("m"); }), "rig.toml:1: [m] must be a table");
  EXPECT_EQ(ErrorOf("[m]\nlist = [\"a\",\n  2]\n", [](const ConfigFile& f) { f.Section("m").Strings("list"); }),
            "rig.toml:3: [m] list must be an array of strings");
  EXPECT_NE(ErrorOf("[m\n", [](const ConfigFile&) {}).find("rig.toml:1:"), std::string::npos);
  EXPECT_EQ(ErrorOf("[m]\nx = 1\n", [](const ConfigFile& f) { f.Section("m").Fail("x", "x is wrong"); }),
            "rig.toml:2: x is wrong");
}

TEST(ConfigFile, NestedTablesComeByKeyAndArraysOfTablesInFileOrderWithTheirLines) {
  const ConfigFile file = ConfigFile::Parse(
      "[rig.effects.zeta]\nk = 1\n[rig.effects.alpha]\nk = 2\n[[member]]\nname = \"a\"\n[[member]]\nname = \"b\"\n"
      "env = { X = 1 }\nargs = [\"x\",\n  \"${Y}\"]\n",
      "g.toml");
  const auto effects = file.Section("rig").Table("effects").Tables();
  ASSERT_EQ(effects.size(), 2u);
  EXPECT_EQ(effects[0].first, "alpha");
  EXPECT_EQ(effects[1].second.name(), "rig.effects.zeta");
  EXPECT_EQ(effects[1].second.label(), "[rig.effects.zeta]");
  EXPECT_EQ(effects[1].second.Integer("k", 0), 1);
  const std::vector<ConfigSection> members = file.Root().TableArray("member");
  ASSERT_EQ(members.size(), 2u);
  EXPECT_EQ(members[1].String("name", ""), "b");
  EXPECT_EQ(members[1].label(), "[[member]] #2");
  // A value under an element is named by the element: "[[member]] #2 env X".
  EXPECT_EQ(test_support::ThrownMessage<ConfigError>([&] { members[1].Table("env").String("X", ""); }),
            "g.toml:9: [[member]] #2 env X must be a string");
  EXPECT_EQ(test_support::ThrownMessage<ConfigError>([&] { members[1].FailAtElement("args", 1, "bad arg"); }),
            "g.toml:11: bad arg");
}

TEST(ConfigFile, ASectionOutlivesTheFileItCameFrom) {
  ConfigSection drive = ConfigFile::Parse("[drive]\nlead_m = 0.02\n", "rig.toml").Section("drive");
  EXPECT_DOUBLE_EQ(drive.Number("lead_m", 0.0), 0.02);
  EXPECT_EQ(drive.origin(), "rig.toml");
}

TEST(ConfigFile, AnUnreadableFileIsNamed) {
  EXPECT_EQ(test_support::ThrownMessage<ConfigError>([] { ConfigFile::ReadText("/nonexistent/rig.toml"); }),
            "/nonexistent/rig.toml: cannot open file");
}

}  // namespace
}  // namespace edsp
