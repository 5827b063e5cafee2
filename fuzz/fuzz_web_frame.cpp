// libFuzzer: what a browser or a script sends edsp-web before anything is
// trusted: a client's text and binary frames (foxglove.websocket.v1), an
// operator's request as JSON for each request channel, and a request's
// target and headers (its token, its Origin, the static file its path
// names). Each either yields a well-formed result or refuses; a static path
// never leaves the panel's folder.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "edsp/channels.h"
#include "edsp/web/foxglove_protocol.h"
#include "edsp/web/http_access.h"
#include "edsp/web/request_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 16)) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)edsp::web::foxglove::ParseClientText(text, 256);
  } catch (const edsp::web::foxglove::ProtocolError&) {
  }
  try {
    (void)edsp::web::foxglove::ParseClientBinary(text);
  } catch (const edsp::web::foxglove::ProtocolError&) {
  }
  for (const char* channel :
       {edsp::channel::kMotionRequest, edsp::channel::kArm, edsp::channel::kPrMode, edsp::channel::kCalibration}) {
    try {
      (void)edsp::web::RequestFromJson(channel, text);
    } catch (const edsp::web::foxglove::ProtocolError&) {
    }
  }
  // The same bytes as a request's parts: target, header, path.
  (void)edsp::web::PresentedToken(text, text);
  (void)edsp::web::OriginAllowed(text, "rig:8765", {"https://allowed.example"});
  if (const auto file = edsp::web::StaticFile("/panel", edsp::web::TargetPath(text))) {
    if (file->rfind("/panel/", 0) != 0 || file->find("/..") != std::string::npos) std::abort();
  }
  return 0;
}
