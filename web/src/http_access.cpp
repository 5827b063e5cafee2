#include "edsp/web/http_access.h"

#include <iterator>

namespace edsp::web {
namespace {

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::string PercentDecoded(std::string_view text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && HexDigit(text[i + 1]) >= 0 && HexDigit(text[i + 2]) >= 0) {
      out.push_back(static_cast<char>(HexDigit(text[i + 1]) * 16 + HexDigit(text[i + 2])));
      i += 2;
    } else {
      out.push_back(text[i] == '+' ? ' ' : text[i]);
    }
  }
  return out;
}

}  // namespace

std::string_view TargetPath(std::string_view target) { return target.substr(0, target.find('?')); }

std::optional<std::string> QueryValue(std::string_view target, std::string_view key) {
  const std::size_t question = target.find('?');
  if (question == std::string_view::npos) return std::nullopt;
  std::string_view query = target.substr(question + 1);
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    const std::size_t eq = pair.find('=');
    if (pair.substr(0, eq) == key) {
      return eq == std::string_view::npos ? std::string() : PercentDecoded(pair.substr(eq + 1));
    }
    if (amp == std::string_view::npos) break;
    query.remove_prefix(amp + 1);
  }
  return std::nullopt;
}

std::optional<std::string> PresentedToken(std::string_view target, std::string_view authorization_header) {
  if (auto token = QueryValue(target, "token")) return token;
  constexpr std::string_view kBearer = "Bearer ";
  if (authorization_header.substr(0, kBearer.size()) == kBearer) {
    return std::string(authorization_header.substr(kBearer.size()));
  }
  return std::nullopt;
}

bool PathNeedsToken(std::string_view path) {
  const auto ends_with = [path](std::string_view end) {
    return path.size() >= end.size() && path.substr(path.size() - end.size()) == end;
  };
  return path == "/" || path.empty() || ends_with(".html") || ends_with(".json");
}

bool OriginAllowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed) {
  if (origin.empty()) return true;
  if (!host.empty() && (origin == "http://" + std::string(host) || origin == "https://" + std::string(host))) {
    return true;
  }
  for (const std::string& a : allowed) {
    if (origin == a) return true;
  }
  return false;
}

bool LoopbackHost(std::string_view host) {
  std::string_view name = host;
  if (!name.empty() && name.front() == '[') {
    name = name.substr(0, name.find(']') + 1);  // [::1]:8765 -> [::1]
  } else {
    name = name.substr(0, name.find(':'));
  }
  if (name == "localhost" || name == "[::1]") return true;
  // 127.0.0.0/8, as four decimal numbers
  if (name.substr(0, 4) != "127.") return false;
  int dots = 0;
  for (char c : name) {
    if (c == '.')
      ++dots;
    else if (c < '0' || c > '9')
      return false;
  }
  return dots == 3 && name.back() != '.';
}

std::optional<std::string> StaticFile(const std::string& root, std::string_view path) {
  if (path.empty() || path.front() != '/') return std::nullopt;
  std::string_view name = path.substr(1);
  if (name.empty()) name = "index.html";
  if (name.find('\\') != std::string_view::npos || name.find('\0') != std::string_view::npos) return std::nullopt;
  // Each part a plain name: no "..", no ".hidden", no empty part ("a//b").
  std::string_view rest = name;
  while (true) {
    const std::size_t slash = rest.find('/');
    const std::string_view part = rest.substr(0, slash);
    if (part.empty() || part.front() == '.') return std::nullopt;
    if (slash == std::string_view::npos) break;
    rest.remove_prefix(slash + 1);
  }
  return root + "/" + std::string(name);
}

const char* ContentType(std::string_view file) {
  const std::size_t dot = file.rfind('.');
  const std::string_view ext = dot == std::string_view::npos ? "" : file.substr(dot + 1);
  if (ext == "html") return "text/html; charset=utf-8";
  if (ext == "js" || ext == "mjs") return "text/javascript; charset=utf-8";
  if (ext == "css") return "text/css; charset=utf-8";
  if (ext == "json") return "application/json";
  if (ext == "svg") return "image/svg+xml";
  if (ext == "png") return "image/png";
  return "application/octet-stream";
}

bool LoginLimiter::Blocked(const std::string& address, Clock::time_point now) {
  const auto it = records_.find(address);
  if (it == records_.end()) return false;
  if (now - it->second.last >= window_) {
    records_.erase(it);
    return false;
  }
  return it->second.failures >= max_failures_;
}

void LoginLimiter::Failed(const std::string& address, Clock::time_point now) {
  if (records_.size() >= kMaxAddresses) {  // bounded however many addresses try
    for (auto it = records_.begin(); it != records_.end();) {
      it = now - it->second.last >= window_ ? records_.erase(it) : std::next(it);
    }
    if (records_.size() >= kMaxAddresses) records_.erase(records_.begin());
  }
  Record& r = records_[address];
  if (r.failures > 0 && now - r.last >= window_) r.failures = 0;
  ++r.failures;
  r.last = now;
}

}  // namespace edsp::web
