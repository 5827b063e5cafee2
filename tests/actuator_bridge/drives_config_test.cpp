// [drives] of the platform config: defaults, a Modbus TCP rig's drives with
// their scaling (checked against the lead and gear by hand), and every bad
// value refused with the file, line and key.
#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "edsp/actuator_bridge/backend_registry.h"
#include "edsp/actuator_bridge/drives_config.h"
#include "thrown_message.h"  // tests/support

namespace edsp {
namespace {

std::string ErrorOf(const std::string& text) {
  return test_support::ThrownMessage<ConfigError>([&] { ParseDrivesConfig(text, "rig.toml", DriveParameters{}); },
                                                  "no error");
}

const std::string kModbusSection =
    "[drives]\nbackend = \"modbus-tcp\"\nhost = \"10.0.0.7\"\nport = 502\nresponse_timeout_ms = 4\n"
    "counts_per_m = 104857600\n";
// A Modbus rig's [drives] with its counts per metre given as `counts` (line 3).
std::string ModbusCounts(const std::string& counts) {
  return "[drives]\nbackend = \"modbus-tcp\"\ncounts_per_m = " + counts + "\n";
}

TEST(DrivesConfig, WithoutASectionTheVirtualDrives) {
  const DrivesConfig c = ParseDrivesConfig("[drive]\nlead_m = 0.01\n", "rig.toml", DriveParameters{});
  EXPECT_EQ(c.backend, "virtual-rig");
  EXPECT_TRUE(c.backend_note.empty());
}

TEST(DrivesConfig, TheOldSpellingOfTheVirtualRigIsTakenWithANoteNamingTheNew) {
  const DrivesConfig c = ParseDrivesConfig("[drives]\nbackend = \"virtual\"\n", "rig.toml", DriveParameters{});
  EXPECT_EQ(c.backend, "virtual-rig");
  EXPECT_NE(c.backend_note.find("now spelled \"virtual-rig\""), std::string::npos) << c.backend_note;
}

TEST(BackendRegistry, EachBackendOnceByNameAndMadeByItsRow) {
  std::set<std::string> names;
  for (const BackendKind& k : BackendKinds()) {
    EXPECT_TRUE(names.insert(std::string(k.name)).second) << k.name << " twice";
    EXPECT_FALSE(k.description.empty());
    std::string note;
    EXPECT_EQ(FindBackend(std::string(k.name), &note), &k);
    EXPECT_TRUE(note.empty());
  }
  // Names users' configs and command lines rely on: a backend may be
  // added beside them, none renamed away.
  for (const char* contract : {"virtual-rig", "modbus-tcp", "cia402-shm"}) {
    EXPECT_EQ(names.count(contract), 1u) << contract;
  }
  std::string note = "stale";
  EXPECT_EQ(FindBackend("ethercat", &note), nullptr);
  EXPECT_TRUE(note.empty());
  const std::string known = KnownBackends();
  EXPECT_EQ(known.rfind("virtual-rig, ", 0), 0u) << known << ": the default first, in the table's order";
  EXPECT_EQ(std::count(known.begin(), known.end(), ','), static_cast<long>(BackendKinds().size()) - 1) << known;
}

TEST(DrivesConfig, AModbusRigsDrivesAndTheirScaling) {
  DriveParameters drive;
  drive.lead_m = 0.005;
  drive.gear_ratio = 2.0;
  const DrivesConfig c = ParseDrivesConfig(
      kModbusSection + "offset_counts = [0, 1, 2, 3, 4, -5]\ndirection = [1, 1, 1, -1, -1, -1]\n", "rig.toml", drive);
  EXPECT_EQ(c.backend, "modbus-tcp");
  EXPECT_EQ(c.host, "10.0.0.7");
  EXPECT_EQ(c.port, 502);
  EXPECT_DOUBLE_EQ(c.response_timeout_s, 0.004);
  // One motor turn = lead / gear = 2.5 mm of leg = 262 144 counts at 2^20·100 per metre.
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(*c.scaling[i].ToCounts(2.0 * M_PI) - c.scaling[i].offset_counts, (i < 3 ? 1 : -1) * 262144, 1)
        << "leg " << i + 1;
  }
  EXPECT_EQ(c.scaling[5].offset_counts, -5);
}

TEST(DrivesConfig, BadValuesAreNamedWithTheirLine) {
  EXPECT_NE(ErrorOf("[drives]\nbackend = \"ethercat\"\n").find("rig.toml:2: [drives] backend = \"ethercat\""),
            std::string::npos);
  EXPECT_NE(ErrorOf("[drives]\nbackend = \"modbus-tcp\"\n").find("needs counts_per_m"), std::string::npos);
  EXPECT_NE(ErrorOf(kModbusSection + "port = 0\n").find("rig.toml:7:"), std::string::npos)
      << "TOML refuses a second port";
  EXPECT_NE(ErrorOf("[drives]\nport = 70000\n").find("rig.toml:2: [drives] port = 70000"), std::string::npos);
  EXPECT_NE(ErrorOf("[drives]\nport = 4294968798\n").find("port = 4294968798"), std::string::npos) << "never wrapped";
  EXPECT_NE(ErrorOf("[drives]\nport = 502.5\n").find("must be an integer"), std::string::npos);
  EXPECT_NE(ErrorOf("[drives]\nresponse_timeout_ms = 0\n").find("response_timeout_ms = 0"), std::string::npos);
  EXPECT_NE(ErrorOf(ModbusCounts("-1")).find("rig.toml:3: [drives] leg 1: counts_per_m = -1 must be positive"),
            std::string::npos);
  EXPECT_NE(ErrorOf(ModbusCounts("[1, 2, 3, 4, 5, 0]")).find("leg 6: counts_per_m = 0"), std::string::npos);
  EXPECT_NE(ErrorOf(ModbusCounts("nan")).find("must be finite"), std::string::npos);
  EXPECT_NE(ErrorOf(ModbusCounts("[1, 2]")).find("array of 6"), std::string::npos);
  EXPECT_NE(ErrorOf(kModbusSection + "direction = [1, 1, 0, 1, 1, 1]\n").find("leg 3: direction"), std::string::npos);
  EXPECT_NE(ErrorOf(kModbusSection + "offset_counts = 0.5\n").find("offset_counts of leg 1 = 0.5"), std::string::npos);
  EXPECT_NE(ErrorOf(kModbusSection + "offset_counts = 3e9\n").find("32-bit"), std::string::npos);
  EXPECT_NE(ErrorOf(kModbusSection + "counts = 1\n").find("unknown key [drives] counts"), std::string::npos);
}

}  // namespace
}  // namespace edsp
