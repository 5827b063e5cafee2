#pragma once
// `edsp-web token add|list|revoke`: the tokens file edited under its lock
// (TokenFileLock), so two operators adding tokens at once lose neither.

#include <string>

namespace edsp::web {

// A new token for `name` with `role` ("viewer" or "operator"), printed once
// on stdout: the file keeps its hash only.
void AddToken(const std::string& path, const std::string& name, const std::string& role);
// Each name and its role, a line each, on stdout.
void ListTokens(const std::string& path);
// `name`'s token removed; throws std::invalid_argument naming an unknown name.
void RevokeToken(const std::string& path, const std::string& name);

}  // namespace edsp::web
