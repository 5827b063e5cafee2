#pragma once
// A reply's code (reply_t.CODE_*, also motion_reply_t.code) as a type, its
// name and its family, once: the nodes answer with it, edsp-ctl takes its
// exit code from it and Python its exception class (docs/interfaces.md §7).
// A new code is a constant in reply_t.lcm and a row here.

#include <cstdint>
#include <string_view>

#include "edsp/reply_t.hpp"

namespace edsp {

enum class ReplyCode : std::int8_t {
  kDone = reply_t::CODE_DONE,
  kInvalid = reply_t::CODE_INVALID,
  kNotNow = reply_t::CODE_NOT_NOW,
  kOutOfLimits = reply_t::CODE_OUT_OF_LIMITS,
  kFailed = reply_t::CODE_FAILED,
  kOtherSession = reply_t::CODE_OTHER_SESSION,
  kStale = reply_t::CODE_STALE,
};

// What a client does with a reply: carry on, take no for an answer (the
// request was not acted on; asking otherwise may succeed), or treat the
// node as failed.
enum class ReplyFamily { kDone, kRefused, kFailed };

struct ReplyCodeRow {
  ReplyCode code;
  std::string_view name;  // as edsp-ctl --json and Python print it
  ReplyFamily family;
};

inline constexpr ReplyCodeRow kReplyCodes[] = {
    {ReplyCode::kDone, "done", ReplyFamily::kDone},
    {ReplyCode::kInvalid, "invalid", ReplyFamily::kRefused},
    {ReplyCode::kNotNow, "not_now", ReplyFamily::kRefused},
    {ReplyCode::kOutOfLimits, "out_of_limits", ReplyFamily::kRefused},
    {ReplyCode::kFailed, "failed", ReplyFamily::kFailed},
    {ReplyCode::kOtherSession, "other_session", ReplyFamily::kRefused},
    {ReplyCode::kStale, "stale", ReplyFamily::kRefused},
};

// The row of a code as it came off the wire; a code this build does not
// know (a newer node's) is a refusal named "unknown".
constexpr const ReplyCodeRow* FindReplyCode(std::int8_t wire) {
  for (const ReplyCodeRow& row : kReplyCodes) {
    if (static_cast<std::int8_t>(row.code) == wire) return &row;
  }
  return nullptr;
}

constexpr ReplyFamily FamilyOf(std::int8_t wire) {
  const ReplyCodeRow* row = FindReplyCode(wire);
  return row != nullptr ? row->family : ReplyFamily::kRefused;
}

constexpr std::string_view ReplyCodeName(std::int8_t wire) {
  const ReplyCodeRow* row = FindReplyCode(wire);
  return row != nullptr ? row->name : std::string_view("unknown");
}

}  // namespace edsp
