#pragma once
// A message of any edsp type, known only by the fingerprint its bytes start
// with (a log's events, a recorder's raw subscription): decoded as that type
// for code that then handles it field by field (message_fields.h).

#include <cstddef>
#include <cstdint>
#include <string>

#include "edsp/logger/log_reader.h"
#include "edsp/message_fields.h"
#include "edsp/transport/decode.h"

namespace edsp {

// Decodes `data` as the edsp type its fingerprint names and calls
// f(const Msg&, "edsp.<type>"): a type of today's or an older layout that
// logs recorded (LegacyMessageTypes). False, without calling f, for a
// foreign fingerprint or bytes that do not decode (truncated, damaged).
template <typename F>
bool DecodeEdspMessage(const std::uint8_t* data, std::size_t size, F&& f) {
  EdspHeader header;
  if (!ParseEdspHeader(data, size, &header)) return false;
  bool decoded = false;
  ForEachLoggedMessageType([&](auto tag) {
    using Msg = typename decltype(tag)::type;
    if (decoded || Msg::getHash() != header.fingerprint) return;
    Msg msg;
    if (!DecodeUntrusted(&msg, data, size)) return;
    decoded = true;
    f(msg, std::string("edsp.") + Msg::getTypeName());
  });
  return decoded;
}

}  // namespace edsp
