#include "edsp/web/token_store.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include "edsp/config_file/config_file.h"

namespace edsp::web {
namespace {

constexpr std::size_t kTokenBytes = 24;  // 192 bits: not guessable at any rate limit

std::string Hex(const unsigned char* data, std::size_t size) {
  std::string out;
  out.reserve(2 * size);
  for (std::size_t i = 0; i < size; ++i) out += fmt::format("{:02x}", data[i]);
  return out;
}

std::string Sha256Hex(std::string_view text) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(text.data(), text.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  }
  return Hex(digest.data(), length);
}

bool IsValidName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                    c == '_' || c == '.' || c == '@';
    if (!ok) return false;
  }
  return true;
}

bool IsSha256Hex(const std::string& text) {
  if (text.size() != 64) return false;
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

void RefuseReadableByOthers(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) return;
  if ((st.st_mode & 077) != 0) {
    throw std::runtime_error(
        fmt::format("{}: mode {:04o} lets others read the token hashes; chmod 600 {}", path, st.st_mode & 07777, path));
  }
}

}  // namespace

const char* RoleName(Role role) { return role == Role::kOperator ? "operator" : "viewer"; }

Role ParseRole(std::string_view text) {
  if (text == "viewer") return Role::kViewer;
  if (text == "operator") return Role::kOperator;
  throw std::invalid_argument("role \"" + std::string(text) + "\": use viewer or operator");
}

TokenStore TokenStore::Load(const std::string& path) {
  TokenStore store;
  if (access(path.c_str(), F_OK) != 0) return store;
  RefuseReadableByOthers(path);
  const ConfigFile file = ConfigFile::Parse(ConfigFile::ReadText(path), path);
  file.Root().RejectUnknownKeys({"token"});
  for (const ConfigSection& t : file.Root().TableArray("token")) {
    t.RejectUnknownKeys({"name", "role", "sha256"});
    TokenEntry entry;
    entry.name = t.String("name", "");
    if (!IsValidName(entry.name)) t.Fail("name", "name \"" + entry.name + "\" is not a token name");
    try {
      entry.role = ParseRole(t.String("role", ""));
    } catch (const std::invalid_argument& e) {
      t.Fail("role", e.what());
    }
    entry.sha256_hex = t.String("sha256", "");
    if (!IsSha256Hex(entry.sha256_hex)) t.Fail("sha256", "sha256 must be 64 lowercase hex digits");
    for (const TokenEntry& other : store.entries_) {
      if (other.name == entry.name) t.Fail("name", "a second token named \"" + entry.name + "\"");
    }
    store.entries_.push_back(std::move(entry));
  }
  return store;
}

std::string TokenStore::Add(const std::string& name, Role role) {
  if (!IsValidName(name)) {
    throw std::invalid_argument("token name \"" + name + "\": 1-64 of letters, digits, '-', '_', '.', '@'");
  }
  for (const TokenEntry& e : entries_) {
    if (e.name == name) throw std::invalid_argument("a token named \"" + name + "\" exists; revoke it first");
  }
  std::array<unsigned char, kTokenBytes> random{};
  if (RAND_bytes(random.data(), static_cast<int>(random.size())) != 1) {
    throw std::runtime_error("no random bytes for a token (OpenSSL RAND_bytes)");
  }
  std::string token = Hex(random.data(), random.size());
  entries_.push_back(TokenEntry{name, role, Sha256Hex(token)});
  return token;
}

void TokenStore::Revoke(const std::string& name) {
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if (it->name == name) {
      entries_.erase(it);
      return;
    }
  }
  throw std::invalid_argument("no token named \"" + name + "\"");
}

void TokenStore::Save(const std::string& path) const {
  std::string text = "# edsp-web tokens: their SHA-256 hashes only (edsp-web token add|list|revoke)\n";
  for (const TokenEntry& e : entries_) {
    text += fmt::format("\n[[token]]\nname = \"{}\"\nrole = \"{}\"\nsha256 = \"{}\"\n", e.name, RoleName(e.role),
                        e.sha256_hex);
  }
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ignored;
  std::filesystem::create_directories(parent, ignored);  // what fails is said below
  // A name of its own (mkstemp: created new, 0600, never through a link),
  // renamed over the file once whole and on disk.
  std::string temporary = path + ".XXXXXX";
  const int fd = mkstemp(temporary.data());
  if (fd < 0) throw std::runtime_error(path + ": cannot create a file beside it (" + std::strerror(errno) + ")");
  std::string failure;
  for (std::size_t done = 0; failure.empty() && done < text.size();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno != EINTR) failure = std::strerror(errno);
    if (n > 0) done += static_cast<std::size_t>(n);
  }
  if (failure.empty() && (fchmod(fd, 0600) != 0 || fsync(fd) != 0)) failure = std::strerror(errno);
  close(fd);
  if (failure.empty() && std::rename(temporary.c_str(), path.c_str()) != 0) failure = std::strerror(errno);
  if (!failure.empty()) {
    std::remove(temporary.c_str());
    throw std::runtime_error(path + ": cannot write (" + failure + ")");
  }
  const int dir = open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {  // the rename itself on disk
    fsync(dir);
    close(dir);
  }
}

TokenFileLock::TokenFileLock(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ignored;
  if (!parent.empty()) std::filesystem::create_directories(parent, ignored);
  const std::string lock_path = path + ".lock";
  fd_ = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd_ < 0 || flock(fd_, LOCK_EX) != 0) {
    const std::string error = std::strerror(errno);
    if (fd_ >= 0) close(fd_);
    throw std::runtime_error(lock_path + ": cannot lock (" + error + ")");
  }
}

TokenFileLock::~TokenFileLock() { close(fd_); }  // the lock goes with it

std::optional<TokenEntry> TokenStore::Check(std::string_view token) const {
  const std::string hash = Sha256Hex(token);
  std::optional<TokenEntry> found;
  for (const TokenEntry& e : entries_) {  // every entry compared: the time says nothing of which matched
    if (CRYPTO_memcmp(hash.data(), e.sha256_hex.data(), hash.size()) == 0) found = e;
  }
  return found;
}

std::string DefaultTokensPath() {
  const char* config = std::getenv("XDG_CONFIG_HOME");
  if (config != nullptr && *config != '\0') return std::string(config) + "/edsp/web_tokens.toml";
  const char* home = std::getenv("HOME");
  return std::string(home != nullptr ? home : ".") + "/.config/edsp/web_tokens.toml";
}

}  // namespace edsp::web
