#include "edsp/web/token_commands.h"

#include <cstdio>

#include "edsp/web/token_store.h"

namespace edsp::web {

void AddToken(const std::string& path, const std::string& name, const std::string& role) {
  const TokenFileLock lock(path);
  TokenStore store = TokenStore::Load(path);
  const std::string token = store.Add(name, ParseRole(role));
  store.Save(path);
  std::printf("%s\n", token.c_str());
  std::fprintf(stderr, "edsp-web: token for %s (%s) added to %s; it is shown only now\n", name.c_str(), role.c_str(),
               path.c_str());
}

void ListTokens(const std::string& path) {
  const TokenStore store = TokenStore::Load(path);
  for (const TokenEntry& e : store.entries()) std::printf("%-24s %s\n", e.name.c_str(), RoleName(e.role));
}

void RevokeToken(const std::string& path, const std::string& name) {
  const TokenFileLock lock(path);
  TokenStore store = TokenStore::Load(path);
  store.Revoke(name);
  store.Save(path);
}

}  // namespace edsp::web
