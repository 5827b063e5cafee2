#pragma once
// Who may use edsp-web: named tokens with a role, kept in a TOML file that
// holds only their SHA-256 hashes (mode 0600; a file others may read is
// refused). A token is shown once, when it is made; a lost one is revoked
// and made anew.
//   [[token]]
//   name = "alice"
//   role = "operator"          # or "viewer"
//   sha256 = "<64 hex digits>"
// viewer: every page and channel, no request; operator: requests too.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace edsp::web {

enum class Role { kViewer, kOperator };
const char* RoleName(Role role);
// "viewer" or "operator"; throws std::invalid_argument naming anything else.
Role ParseRole(std::string_view text);

struct TokenEntry {
  std::string name;
  Role role = Role::kViewer;
  std::string sha256_hex;
};

class TokenStore {
 public:
  // The file's tokens; a file that does not exist is an empty store. Throws
  // ConfigError naming the file, line and key for a malformed one, and
  // std::runtime_error naming it and its mode if others may read it.
  static TokenStore Load(const std::string& path);

  // A new token for `name` (letters, digits, '-', '_', '.', '@'; unique):
  // returns it, keeps only its hash. Throws std::invalid_argument naming a
  // bad or taken name.
  std::string Add(const std::string& name, Role role);
  // Throws std::invalid_argument naming a name with no token.
  void Revoke(const std::string& name);
  // Writes the store (mode 0600, replaced whole: a crash leaves the old or
  // the new file). Throws std::runtime_error naming the file.
  void Save(const std::string& path) const;

  // The entry whose token this is (hashes compared in constant time).
  std::optional<TokenEntry> Check(std::string_view token) const;
  const std::vector<TokenEntry>& entries() const { return entries_; }

 private:
  std::vector<TokenEntry> entries_;
};

// Holds the tokens file for one read-change-write (`edsp-web token add`
// and `revoke` at once must not lose one's change): an exclusive flock on
// FILE.lock until destroyed. Throws std::runtime_error naming it.
class TokenFileLock {
 public:
  explicit TokenFileLock(const std::string& path);
  ~TokenFileLock();
  TokenFileLock(const TokenFileLock&) = delete;
  TokenFileLock& operator=(const TokenFileLock&) = delete;

 private:
  int fd_ = -1;
};

// The default tokens file: $XDG_CONFIG_HOME/edsp/web_tokens.toml, else
// ~/.config/edsp/web_tokens.toml.
std::string DefaultTokensPath();

}  // namespace edsp::web
