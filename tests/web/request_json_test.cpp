// An operator's request from JSON: every request type through the JSON a
// browser writes and back to the very bytes (a round trip through
// MessageToJson, the other direction of the same field table), and every
// wrong field refused by name.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "edsp/channels.h"
#include "edsp/web/foxglove_protocol.h"
#include "edsp/web/message_json.h"
#include "edsp/web/request_json.h"
#include "encoded.h"  // tests/support

namespace edsp::web {
namespace {

template <typename Msg>
void ExpectRoundTrip(const char* channel, const Msg& msg) {
  const std::vector<std::uint8_t> bytes = test_support::Encoded(msg);
  nlohmann::ordered_json as_json;
  ASSERT_TRUE(MessageToJson(bytes.data(), bytes.size(), &as_json));
  const RequestMessage back = RequestFromJson(channel, as_json.dump());
  ASSERT_TRUE(std::holds_alternative<Msg>(back)) << channel;
  EXPECT_EQ(test_support::Encoded(std::get<Msg>(back)), bytes) << channel << ": " << as_json.dump();
}

TEST(RequestFromJson, EveryRequestTypeComesBackToItsBytes) {
  motion_request_t move{};
  move.utime = 1'700'000'000'000'001;
  move.seq = 3;
  move.session_id = 9;
  move.request_id = -8'000'000'000'000'000'001;
  move.client = "web:alice";
  move.kind = motion_request_t::KIND_MOVE;
  move.relative = 1;
  move.frame = "fixture";
  for (int i = 0; i < 6; ++i) move.pose[i] = 0.001 * (i + 1) + 1e-15;
  move.point[2] = 0.3;
  move.speed_m_s = 0.05;
  move.motions = "Lz,Rz";
  move.csv_text = "t,x\n0,\"1\"\n";
  ExpectRoundTrip(channel::kMotionRequest, move);

  arm_t arm{};
  arm.request_id = 5;
  arm.operator_name = "web:bob";
  ExpectRoundTrip(channel::kArm, arm);

  pr_mode_t mode{};
  mode.request_id = 6;
  mode.pr_mode = 2;
  ExpectRoundTrip(channel::kPrMode, mode);

  calibration_t calibration{};
  calibration.request_id = 7;
  calibration.model_json = R"({"format": "edsp-gap-model/1", "effects": []})";
  calibration.apply_ambiguous = 1;
  ExpectRoundTrip(channel::kCalibration, calibration);
}

TEST(RequestFromJson, AbsentFieldsStayZeroAndBooleansFitFlags) {
  const RequestMessage r =
      RequestFromJson(channel::kMotionRequest, R"({"request_id": 4, "kind": 4, "relative": true})");
  const auto& m = std::get<motion_request_t>(r);
  EXPECT_EQ(m.request_id, 4);
  EXPECT_EQ(m.kind, motion_request_t::KIND_HALT);
  EXPECT_EQ(m.relative, 1);
  EXPECT_EQ(m.pose[3], 0.0);
  EXPECT_EQ(m.client, "");
}

TEST(RequestFromJson, WrongFieldsAndChannelsAreRefusedByName) {
  const std::pair<std::pair<const char*, const char*>, const char*> cases[] = {
      {{channel::kMotionRequest, R"({"request_id": 1, "pose": [0, 0, 1]})"}, "pose must be an array of 6"},
      {{channel::kMotionRequest, R"({"pose": [0, 0, "1", 0, 0, 0]})"}, "pose[2] must be a number"},
      {{channel::kMotionRequest, R"({"kind": 300})"}, "kind must be an integer that fits"},
      {{channel::kMotionRequest, R"({"kind": -129})"}, "kind must be an integer that fits"},
      {{channel::kMotionRequest, R"({"request_id": 1.5})"}, "request_id must be an integer"},
      {{channel::kMotionRequest, R"({"request_id": 18446744073709551615})"}, "request_id must be an integer that fits"},
      {{channel::kMotionRequest, R"({"speed_m_s": 1e999})"}, "not a JSON object"},  // JSON has no infinity
      {{channel::kMotionRequest, R"({"frame": 3})"}, "frame must be a string"},
      {{channel::kMotionRequest, R"({"posee": [0, 0, 0, 0, 0, 0]})"}, "has no field \"posee\""},
      {{channel::kMotionRequest, R"([1, 2])"}, "not a JSON object"},
      {{channel::kArm, R"({"pr_mode": 1})"}, "arm_t has no field \"pr_mode\""},
      {{channel::kLegCommand, R"({})"}, "EDSP_LEG_COMMAND is not a request channel"},
  };
  for (const auto& [input, named] : cases) {
    try {
      RequestFromJson(input.first, input.second);
      ADD_FAILURE() << input.second << " was taken";
    } catch (const foxglove::ProtocolError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << input.second << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(input.first), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(IsRequestChannel(channel::kArm));
  EXPECT_FALSE(IsRequestChannel(channel::kSetpoint));
}

}  // namespace
}  // namespace edsp::web
