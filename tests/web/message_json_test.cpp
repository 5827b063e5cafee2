// Messages as JSON and their schemas, against the .lcm files' own field
// lists (read here, apart from message_fields.h) and against the values
// encoded: every type, every field, with the values a message carried.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/fault_t.hpp"
#include "edsp/leg_state_t.hpp"
#include "edsp/message_types.h"
#include "edsp/node/build_paths.h"
#include "edsp/platform_config_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/web/message_json.h"
#include "encoded.h"  // tests/support

namespace edsp::web {
namespace {

using json = nlohmann::ordered_json;

using test_support::Encoded;

template <typename Msg>
json AsJson(const Msg& msg, std::string* type = nullptr) {
  const std::vector<std::uint8_t> bytes = Encoded(msg);
  json out;
  EXPECT_TRUE(MessageToJson(bytes.data(), bytes.size(), &out, type));
  return out;
}

// The fields a .lcm file declares, in order: "name" and its array sizes.
struct LcmField {
  std::string name;
  std::string type;
  std::vector<int> dims;
};
std::vector<LcmField> FieldsOfLcmFile(const std::string& type_name) {
  std::ifstream in(SourcePath("lcmtypes/" + type_name + ".lcm"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string body = std::regex_replace(text.str(), std::regex("//[^\n]*"), "");
  std::vector<LcmField> fields;
  const std::regex field(R"(^\s*(\w+)\s+(\w+)((?:\s*\[\s*\d+\s*\])*)\s*;)");
  std::istringstream lines(body.substr(body.find('{') + 1));
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (line.find("const") != std::string::npos || !std::regex_search(line, m, field)) continue;
    LcmField f{m[2], m[1], {}};
    const std::string dims = m[3];
    static const std::regex number(R"(\d+)");
    for (std::sregex_iterator it(dims.begin(), dims.end(), number), end; it != end; ++it) {
      f.dims.push_back(std::stoi(it->str()));
    }
    fields.push_back(f);
  }
  return fields;
}

// The schema of one field, checked against its .lcm declaration.
void ExpectFieldSchema(const json& schema, const LcmField& f, std::size_t depth, const std::string& where) {
  if (depth < f.dims.size()) {
    ASSERT_EQ(schema.at("type"), "array") << where;
    EXPECT_EQ(schema.at("minItems"), f.dims[depth]) << where;
    EXPECT_EQ(schema.at("maxItems"), f.dims[depth]) << where;
    ExpectFieldSchema(schema.at("items"), f, depth + 1, where);
    return;
  }
  if (f.type == "double") {
    EXPECT_EQ(schema.at("type"), json::array({"number", "null"})) << where;
  } else if (f.type == "string") {
    EXPECT_EQ(schema.at("type"), "string") << where;
  } else {
    EXPECT_EQ(schema.at("type"), "integer") << where << " (" << f.type << ")";
  }
}

TEST(MessageSchema, EveryTypeHasEveryFieldOfItsLcmFileRequiredWithItsTypeAndShape) {
  int types = 0;
  ForEachMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    const std::string name = Msg::getTypeName();
    const json schema = MessageSchema(name);
    const std::vector<LcmField> fields = FieldsOfLcmFile(name);
    ASSERT_FALSE(fields.empty()) << name;
    EXPECT_EQ(schema.at("title"), "edsp." + name);
    ASSERT_EQ(schema.at("required").size(), fields.size()) << name;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      EXPECT_EQ(schema.at("required")[i], fields[i].name) << name;
      ExpectFieldSchema(schema.at("properties").at(fields[i].name), fields[i], 0, name + "." + fields[i].name);
    }
    ++types;
  });
  EXPECT_EQ(types, static_cast<int>(kMessageTypeCount));
  EXPECT_THROW(MessageSchema("no_such_t"), std::invalid_argument);
}

TEST(MessageToJson, CarriesEveryValueAsEncodedWithTheLcmNames) {
  pose_setpoint_t m{};
  m.utime = 1'700'000'000'123'456;
  m.seq = -7;
  m.session_id = 42;
  for (int i = 0; i < 6; ++i) {
    m.pose[i] = 0.1 * (i + 1) + 1e-12;
    m.velocity[i] = -0.5 * i;
    m.acceleration[i] = 3.0 * i;
  }
  m.trajectory = "paper motion 1";
  m.segment = -3;
  std::string type;
  const json j = AsJson(m, &type);
  EXPECT_EQ(type, "edsp.pose_setpoint_t");
  EXPECT_EQ(j.at("utime").get<std::int64_t>(), m.utime);
  EXPECT_EQ(j.at("seq").get<std::int64_t>(), m.seq);
  EXPECT_EQ(j.at("session_id").get<std::int64_t>(), 42);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(j.at("pose")[i].get<double>(), m.pose[i]);  // exact: the double's own digits
    EXPECT_EQ(j.at("velocity")[i].get<double>(), m.velocity[i]);
  }
  EXPECT_EQ(j.at("trajectory"), "paper motion 1");
  EXPECT_EQ(j.at("segment").get<int>(), -3);
}

TEST(MessageToJson, MatricesNestAndTextAndSmallIntegersStayThemselves) {
  platform_config_t c{};
  c.base_joints_m[5][2] = -1.25;
  c.preset = "paper \"Table 1\"\n";
  c.config_toml = "[drive]\nlead_m = 0.01\n";
  c.pr_sign = -1;
  const json j = AsJson(c);
  ASSERT_EQ(j.at("base_joints_m").size(), 6u);
  ASSERT_EQ(j.at("base_joints_m")[5].size(), 3u);
  EXPECT_EQ(j.at("base_joints_m")[5][2].get<double>(), -1.25);
  EXPECT_EQ(j.at("preset"), c.preset);
  EXPECT_EQ(j.at("config_toml"), c.config_toml);
  // Through text and back, as a browser gets it.
  EXPECT_EQ(json::parse(j.dump()).at("preset"), c.preset);

  fault_t f{};
  f.severity = 2;
  f.code = -5;
  const json fj = AsJson(f);
  EXPECT_TRUE(fj.at("severity").is_number_integer());  // an int8 is a number, not a character
  EXPECT_EQ(fj.at("severity").get<int>(), 2);
  EXPECT_EQ(fj.at("code").get<int>(), -5);
}

TEST(MessageToJson, NonFiniteValuesBecomeNullWhichTheSchemaAllows) {
  leg_state_t s{};
  s.encoder_length_m[0] = std::numeric_limits<double>::quiet_NaN();
  s.encoder_length_m[1] = std::numeric_limits<double>::infinity();
  s.encoder_length_m[2] = 1.5;
  const json j = AsJson(s);
  EXPECT_TRUE(j.at("encoder_length_m")[0].is_null());
  EXPECT_TRUE(j.at("encoder_length_m")[1].is_null());
  EXPECT_EQ(j.at("encoder_length_m")[2].get<double>(), 1.5);
  EXPECT_NO_THROW(json::parse(j.dump()));  // valid JSON: no NaN literal
}

TEST(MessageToJson, ForeignTruncatedAndEmptyBytesAreRefused) {
  pose_setpoint_t m{};
  std::vector<std::uint8_t> bytes = Encoded(m);
  json out = "untouched";
  std::vector<std::uint8_t> truncated(bytes.begin(), bytes.end() - 1);
  EXPECT_FALSE(MessageToJson(truncated.data(), truncated.size(), &out));
  std::vector<std::uint8_t> foreign = bytes;
  foreign[0] ^= 0xff;  // another fingerprint
  EXPECT_FALSE(MessageToJson(foreign.data(), foreign.size(), &out));
  EXPECT_FALSE(MessageToJson(bytes.data(), 0, &out));
  EXPECT_EQ(out, "untouched");
}

}  // namespace
}  // namespace edsp::web
