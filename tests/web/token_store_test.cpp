// Tokens: made, checked, revoked and kept across a save and a load; the
// file holds hashes only, at mode 0600; a file others may read, or a
// malformed one, is refused naming the file, line and key.
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "edsp/config_file/config_error.h"
#include "edsp/web/token_store.h"
#include "scratch_dir.h"  // tests/support

namespace edsp::web {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void Write(const std::string& path, const std::string& text, mode_t mode) {
  std::ofstream(path) << text;
  ::chmod(path.c_str(), mode);
}

TEST(TokenStore, ATokenChecksAsItsNameAndRoleUntilRevokedAcrossSaveAndLoad) {
  const std::string dir = test_support::ScratchDir("web_tokens_1");
  const std::string path = dir + "/sub/tokens.toml";  // its folder made on save
  TokenStore store = TokenStore::Load(path);
  EXPECT_TRUE(store.entries().empty());
  const std::string alice = store.Add("alice", Role::kOperator);
  const std::string bob = store.Add("bob@lab", Role::kViewer);
  EXPECT_EQ(alice.size(), 48u);
  EXPECT_NE(alice, bob);
  store.Save(path);

  const TokenStore loaded = TokenStore::Load(path);
  ASSERT_EQ(loaded.entries().size(), 2u);
  ASSERT_TRUE(loaded.Check(alice).has_value());
  EXPECT_EQ(loaded.Check(alice)->name, "alice");
  EXPECT_EQ(loaded.Check(alice)->role, Role::kOperator);
  EXPECT_EQ(loaded.Check(bob)->role, Role::kViewer);
  std::string near = alice;
  near.back() = near.back() == '0' ? '1' : '0';
  EXPECT_FALSE(loaded.Check(near).has_value());
  EXPECT_FALSE(loaded.Check("").has_value());

  TokenStore revoked = loaded;
  revoked.Revoke("alice");
  revoked.Save(path);
  EXPECT_FALSE(TokenStore::Load(path).Check(alice).has_value());
  EXPECT_TRUE(TokenStore::Load(path).Check(bob).has_value());
  EXPECT_THROW(revoked.Revoke("alice"), std::invalid_argument);
}

TEST(TokenStore, TheFileHoldsHashesOnlyAtMode0600) {
  const std::string dir = test_support::ScratchDir("web_tokens_2");
  const std::string path = dir + "/tokens.toml";
  TokenStore store;
  const std::string token = store.Add("alice", Role::kOperator);
  store.Save(path);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  const std::string text = ReadAll(path);
  EXPECT_EQ(text.find(token), std::string::npos);
  EXPECT_EQ(text.find(token.substr(0, 16)), std::string::npos);
  EXPECT_NE(text.find("sha256 = \""), std::string::npos);
  // Nothing left beside it: the file was written under a name of its own and renamed.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, 1);
}

TEST(TokenStore, TokensAreDrawnAnew) {
  TokenStore store;
  std::set<std::string> tokens;
  for (int i = 0; i < 200; ++i) tokens.insert(store.Add("u" + std::to_string(i), Role::kViewer));
  EXPECT_EQ(tokens.size(), 200u);
}

TEST(TokenStore, BadNamesTakenNamesAndBadRolesAreRefusedByName) {
  TokenStore store;
  store.Add("alice", Role::kViewer);
  EXPECT_THROW(store.Add("alice", Role::kOperator), std::invalid_argument);
  for (const char* bad : {"", "a b", "a/b", "a\"b", "ünï"}) {
    EXPECT_THROW(store.Add(bad, Role::kViewer), std::invalid_argument) << bad;
  }
  EXPECT_THROW(store.Add(std::string(65, 'a'), Role::kViewer), std::invalid_argument);
  EXPECT_THROW(ParseRole("admin"), std::invalid_argument);
  EXPECT_EQ(ParseRole("operator"), Role::kOperator);
}

TEST(TokenStore, AFileOthersMayReadIsRefusedNamingItsMode) {
  const std::string dir = test_support::ScratchDir("web_tokens_3");
  const std::string path = dir + "/tokens.toml";
  Write(path, "", 0644);
  try {
    TokenStore::Load(path);
    FAIL() << "a 0644 tokens file was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0644"), std::string::npos) << e.what();
  }
}

TEST(TokenStore, AMalformedFileIsRefusedAtItsLineAndKey) {
  const std::string dir = test_support::ScratchDir("web_tokens_4");
  const std::string path = dir + "/tokens.toml";
  const std::string hash(64, 'a');
  const std::pair<std::string, std::string> cases[] = {
      {"[[token]]\nname = \"a\"\nrole = \"admin\"\nsha256 = \"" + hash + "\"\n", ":3:"},
      {"[[token]]\nname = \"a\"\nrole = \"viewer\"\nsha256 = \"abc\"\n", ":4:"},
      {"[[token]]\nname = \"a b\"\nrole = \"viewer\"\nsha256 = \"" + hash + "\"\n", ":2:"},
      {"[[token]]\nname = \"a\"\nrole = \"viewer\"\nsha256 = \"" + hash + "\"\ncolour = 1\n",
       ":5: unknown key [[token]] #1 colour"},
      {"[[token]]\nname = \"a\"\nrole = \"viewer\"\nsha256 = \"" + hash +
           "\"\n[[token]]\nname = \"a\"\nrole = \"viewer\"\nsha256 = \"" + hash + "\"\n",
       ":6:"},
  };
  for (const auto& [text, named] : cases) {
    Write(path, text, 0600);
    try {
      TokenStore::Load(path);
      ADD_FAILURE() << text << " was read";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path + named), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << text << ": not a ConfigError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace edsp::web
