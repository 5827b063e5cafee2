#pragma once
// Who a request is and what it may see, decided from its parts alone (no
// socket here, so every rule is tested as a function):
//  - its token: `?token=T` on the URL (what a browser can send on a page's
//    and a WebSocket's URL) or `Authorization: Bearer T`, needed for the
//    pages and the WebSocket; the panel's scripts, styles and libraries are
//    the same for everyone and carry nothing of the rig, so the browser
//    fetches them without one (their URLs cannot carry the page's token);
//  - its Origin: a browser's WebSocket from another site's page is refused
//    (a page on evil.example must not drive the rig through a logged-in
//    operator's browser); none (a script) passes;
//  - the static file a path names, inside its folder only (the panel's, or
//    Debian's browser libraries' under /javascript/);
//  - too many wrong tokens from one address: refused for a while.

#include <chrono>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace edsp::web {

// The path of a request target without its query ("/a/b?x=1" → "/a/b").
std::string_view TargetPath(std::string_view target);
// The value of `key` in the target's query, percent-decoded; none if absent.
std::optional<std::string> QueryValue(std::string_view target, std::string_view key);
// The token a request presents (the query's, else the bearer header's).
std::optional<std::string> PresentedToken(std::string_view target, std::string_view authorization_header);
// Whether a GET of `path` needs a token: a page ("/", *.html) and the
// rig's data (*.json: the drift report) do; a script, style or library
// does not.
bool PathNeedsToken(std::string_view path);

// Whether a WebSocket's Origin header may open it: absent, the served host
// itself ("http://HOST" or "https://HOST" with HOST the Host header,
// port included), or one of `allowed` exactly.
bool OriginAllowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed);

// Whether a request's Host header may be served by a server listening on
// loopback only: a loopback name (localhost, 127.x.x.x, [::1]), any port.
// A page on another site whose name an attacker re-points at 127.0.0.1 (DNS
// rebinding) sends its own name, and is refused.
bool LoopbackHost(std::string_view host);

// The file under `root` a GET of `path` serves ("/" → index.html), or none
// for a path that is not a plain file name under it (no "..", no hidden
// files, no back-slashes, no NUL).
std::optional<std::string> StaticFile(const std::string& root, std::string_view path);
// Content-Type by extension (text/html, text/javascript, ...).
const char* ContentType(std::string_view file);

// Wrong tokens per remote address: after `max_failures` within `window`,
// that address is refused until the window has passed since its last.
class LoginLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  LoginLimiter(int max_failures, Clock::duration window) : max_failures_(max_failures), window_(window) {}
  bool Blocked(const std::string& address, Clock::time_point now);
  void Failed(const std::string& address, Clock::time_point now);

 private:
  static constexpr std::size_t kMaxAddresses = 4096;
  struct Record {
    int failures = 0;
    Clock::time_point last;
  };
  int max_failures_;
  Clock::duration window_;
  std::map<std::string, Record> records_;
};

}  // namespace edsp::web
