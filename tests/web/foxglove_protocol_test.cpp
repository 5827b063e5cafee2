// The foxglove.websocket.v1 frames as the specification lays them out
// (github.com/foxglove/ws-protocol docs/spec.md): byte for byte for the
// binary ones, and every malformed client frame refused by name.
#include <gtest/gtest.h>

#include "edsp/web/foxglove_protocol.h"

namespace edsp::web::foxglove {
namespace {

using nlohmann::json;

TEST(FoxgloveFrames, MessageDataIsOpcodeThenLittleEndianIdAndTimeThenThePayload) {
  const std::string frame = MessageData(0x04030201u, 0x0c0b0a0908070605ull, "{\"a\":1}");
  ASSERT_EQ(frame.size(), 1u + 4u + 8u + 7u);
  const unsigned char expected[13] = {0x01, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0a, 0x0b, 0x0c};
  for (int i = 0; i < 13; ++i) EXPECT_EQ(static_cast<unsigned char>(frame[i]), expected[i]) << "byte " << i;
  EXPECT_EQ(frame.substr(13), "{\"a\":1}");
}

TEST(FoxgloveFrames, ServerInfoStatusAndAdvertiseCarryTheSpecsFields) {
  const json info = json::parse(ServerInfo("edsp-web", "7", {{"group", "sim.toml"}}, false));
  EXPECT_EQ(info.at("op"), "serverInfo");
  EXPECT_EQ(info.at("name"), "edsp-web");
  EXPECT_EQ(info.at("capabilities"), json::array());
  EXPECT_FALSE(info.contains("supportedEncodings"));
  EXPECT_EQ(info.at("sessionId"), "7");
  EXPECT_EQ(info.at("metadata").at("group"), "sim.toml");
  const json publisher = json::parse(ServerInfo("edsp-web", "7", json::object(), true));
  EXPECT_EQ(publisher.at("capabilities"), json::array({"clientPublish"}));
  EXPECT_EQ(publisher.at("supportedEncodings"), json::array({"json"}));

  const json status = json::parse(Status(kError, "bad \"frame\""));
  EXPECT_EQ(status.at("op"), "status");
  EXPECT_EQ(status.at("level"), 2);
  EXPECT_EQ(status.at("message"), "bad \"frame\"");

  const json schema = {{"type", "object"}};
  const json advertise = json::parse(Advertise({ServerChannel{3, "EDSP_FAULT", "edsp.fault_t", schema}}));
  EXPECT_EQ(advertise.at("op"), "advertise");
  const json& c = advertise.at("channels").at(0);
  EXPECT_EQ(c.at("id"), 3);
  EXPECT_EQ(c.at("topic"), "EDSP_FAULT");
  EXPECT_EQ(c.at("encoding"), "json");
  EXPECT_EQ(c.at("schemaName"), "edsp.fault_t");
  EXPECT_EQ(c.at("schemaEncoding"), "jsonschema");
  EXPECT_EQ(json::parse(c.at("schema").get<std::string>()), schema);  // a string holding the schema
}

TEST(FoxgloveClientFrames, SubscribeAndUnsubscribeParse) {
  const ClientOp s =
      ParseClientText(R"({"op":"subscribe","subscriptions":[{"id":0,"channelId":3},{"id":1,"channelId":5}]})", 8);
  ASSERT_EQ(s.kind, ClientOp::kSubscribe);
  ASSERT_EQ(s.subscriptions.size(), 2u);
  EXPECT_EQ(s.subscriptions[1].id, 1u);
  EXPECT_EQ(s.subscriptions[1].channel_id, 5u);
  const ClientOp u = ParseClientText(R"({"op":"unsubscribe","subscriptionIds":[0,4294967295]})", 8);
  ASSERT_EQ(u.kind, ClientOp::kUnsubscribe);
  EXPECT_EQ(u.ids, (std::vector<std::uint32_t>{0, 4294967295u}));
}

TEST(FoxgloveClientFrames, AdvertiseUnadvertiseAndClientMessageDataParse) {
  const ClientOp a = ParseClientText(
      R"({"op":"advertise","channels":[{"id":4,"topic":"EDSP_MOTION_REQUEST","encoding":"json","schemaName":"edsp.motion_request_t"}]})",
      8);
  ASSERT_EQ(a.kind, ClientOp::kAdvertise);
  ASSERT_EQ(a.channels.size(), 1u);
  EXPECT_EQ(a.channels[0].id, 4u);
  EXPECT_EQ(a.channels[0].topic, "EDSP_MOTION_REQUEST");
  EXPECT_EQ(a.channels[0].encoding, "json");
  EXPECT_EQ(a.channels[0].schema_name, "edsp.motion_request_t");
  const ClientOp u = ParseClientText(R"({"op":"unadvertise","channelIds":[4]})", 8);
  ASSERT_EQ(u.kind, ClientOp::kUnadvertise);
  EXPECT_EQ(u.ids, std::vector<std::uint32_t>{4});

  const std::string frame = std::string("\x01\x04\x03\x02\x01", 5) + "{\"kind\":4}";
  const ClientMessage m = ParseClientBinary(frame);
  EXPECT_EQ(m.channel_id, 0x01020304u);
  EXPECT_EQ(m.payload, "{\"kind\":4}");
  EXPECT_EQ(ParseClientBinary(std::string("\x01\x00\x00\x00\x00", 5)).payload, "");
  for (const std::string& bad :
       {std::string(), std::string("\x02\x00\x00\x00\x00{}", 7), std::string("\x01\x00\x00", 3)}) {
    EXPECT_THROW(ParseClientBinary(bad), ProtocolError) << bad.size();
  }
}

// Each malformed frame throws, and its message names what is at fault.
TEST(FoxgloveClientFrames, MalformedFramesAreRefusedNamingTheFault) {
  const std::pair<const char*, const char*> cases[] = {
      {"not json", "not JSON"},
      {"[1,2]", "not a JSON object"},
      {R"({"subscriptions":[]})", "\"op\""},
      {R"({"op":7})", "\"op\""},
      {R"({"op":"publish"})", "\"publish\""},
      {R"({"op":"subscribe"})", "\"subscriptions\""},
      {R"({"op":"subscribe","subscriptions":[{"id":1}]})", "\"channelId\""},
      {R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})", "\"id\" is -1"},
      {R"({"op":"subscribe","subscriptions":[{"id":1.5,"channelId":1}]})", "\"id\" is 1.5"},
      {R"({"op":"subscribe","subscriptions":[{"id":4294967296,"channelId":1}]})", "4294967296"},
      {R"({"op":"subscribe","subscriptions":[7]})", "not an object"},
      {R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":1},{"id":2,"channelId":1},{"id":3,"channelId":1}]})",
       "3 items"},
      {R"({"op":"unsubscribe","subscriptionIds":["a"]})", "\"a\""},
      {R"({"op":"advertise","channels":[{"id":1,"encoding":"json"}]})", "\"topic\""},
      {R"({"op":"advertise","channels":[{"id":1,"topic":"EDSP_ARM"}]})", "\"encoding\""},
      {R"({"op":"unadvertise","channelIds":[-2]})", "-2"},
  };
  for (const auto& [frame, named] : cases) {
    try {
      ParseClientText(frame, 2);
      ADD_FAILURE() << frame << " was taken";
    } catch (const ProtocolError& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << frame << ": " << e.what();
    }
  }
  // Nesting is refused before any JSON parser recurses on it; brackets in strings do not nest.
  const std::string deep = R"({"op":"subscribe","subscriptions":)" + std::string(20, '[') + std::string(20, ']') + "}";
  EXPECT_THROW(ParseClientText(deep, 2), ProtocolError);
  EXPECT_NO_THROW(ParseClientText(R"({"op":"unsubscribe","subscriptionIds":[],"x":"[[[[[[[[[[[[[[[[[[[[\"[["})", 2));
}

}  // namespace
}  // namespace edsp::web::foxglove
