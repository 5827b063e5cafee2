// Who a request is and what it may see, rule by rule.
#include <gtest/gtest.h>

#include "edsp/web/http_access.h"

namespace edsp::web {
namespace {

TEST(HttpAccess, TheTokenComesFromTheQueryElseTheBearerHeader) {
  EXPECT_EQ(PresentedToken("/?token=abc", ""), "abc");
  EXPECT_EQ(PresentedToken("/panel.js?x=1&token=a%2Bb&y", ""), "a+b");
  EXPECT_EQ(PresentedToken("/", "Bearer xyz"), "xyz");
  EXPECT_EQ(PresentedToken("/?token=q", "Bearer h"), "q");
  EXPECT_FALSE(PresentedToken("/", "Basic dXNlcjpwYXNz").has_value());
  EXPECT_FALSE(PresentedToken("/?tokens=abc", "").has_value());
  EXPECT_EQ(PresentedToken("/?token=", ""), "");            // present but empty: checked, and wrong
  EXPECT_EQ(PresentedToken("/?token=%zz%4", ""), "%zz%4");  // a broken escape stays as it is
  EXPECT_EQ(TargetPath("/a/b.js?token=x"), "/a/b.js");
}

TEST(HttpAccess, PagesAndTheRigsDataNeedATokenTheirScriptsStylesAndLibrariesDoNot) {
  for (const char* page : {"/", "", "/index.html", "/a/b.html", "/drift-report.json"}) {
    EXPECT_TRUE(PathNeedsToken(page)) << page;
  }
  for (const char* asset :
       {"/panel.js", "/panel.css", "/javascript/three/three.min.js", "/html", "/x.htm", "/json", "/x.jso"}) {
    EXPECT_FALSE(PathNeedsToken(asset)) << asset;
  }
}

TEST(HttpAccess, AWebSocketsOriginMustBeTheServedHostOrOneAllowed) {
  EXPECT_TRUE(OriginAllowed("", "rig:8765", {}));  // a script, not a browser
  EXPECT_TRUE(OriginAllowed("http://rig:8765", "rig:8765", {}));
  EXPECT_TRUE(OriginAllowed("https://rig:8765", "rig:8765", {}));
  EXPECT_FALSE(OriginAllowed("http://evil.example", "rig:8765", {}));
  EXPECT_FALSE(OriginAllowed("http://rig:8766", "rig:8765", {}));
  EXPECT_FALSE(OriginAllowed("http://rig:8765.evil.example", "rig:8765", {}));
  EXPECT_FALSE(OriginAllowed("http://rig:8765", "", {}));
  EXPECT_TRUE(OriginAllowed("https://app.lichtblick.example", "rig:8765", {"https://app.lichtblick.example"}));
}

TEST(HttpAccess, OnLoopbackOnlyLoopbackNamesAreServed) {
  for (const char* ok : {"localhost", "localhost:8765", "127.0.0.1:8765", "127.1.2.3", "[::1]:8765", "[::1]"}) {
    EXPECT_TRUE(LoopbackHost(ok)) << ok;
  }
  for (const char* bad : {"", "evil.example", "evil.example:8765", "127.0.0.1.evil.example", "127.0.0.1.",
                          "localhost.evil.example", "10.0.0.1:8765", "[::2]:8765", "127.a.0.1"}) {
    EXPECT_FALSE(LoopbackHost(bad)) << bad;
  }
}

TEST(HttpAccess, StaticFilesStayInsideThePanelsFolder) {
  EXPECT_EQ(StaticFile("/p", "/"), "/p/index.html");
  EXPECT_EQ(StaticFile("/p", "/panel.js"), "/p/panel.js");
  EXPECT_EQ(StaticFile("/p", "/lib/three.js"), "/p/lib/three.js");
  for (const char* bad :
       {"/../etc/passwd", "/lib/../../x", "/.hidden", "//etc/passwd", "/a//b", "/a\\b", "a.js", "", "/lib/"}) {
    EXPECT_FALSE(StaticFile("/p", bad).has_value()) << bad;
  }
  EXPECT_FALSE(StaticFile("/p", std::string_view("/a\0b", 4)).has_value());
  EXPECT_STREQ(ContentType("/p/panel.js"), "text/javascript; charset=utf-8");
  EXPECT_STREQ(ContentType("/p/index.html"), "text/html; charset=utf-8");
  EXPECT_STREQ(ContentType("/p/blob"), "application/octet-stream");
}

TEST(HttpAccess, TooManyWrongTokensFromOneAddressBlockItForTheWindow) {
  using namespace std::chrono_literals;
  LoginLimiter limiter(3, 60s);
  const auto t0 = LoginLimiter::Clock::time_point{} + 1h;
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(limiter.Blocked("10.0.0.1", t0 + i * 1s));
    limiter.Failed("10.0.0.1", t0 + i * 1s);
  }
  EXPECT_TRUE(limiter.Blocked("10.0.0.1", t0 + 10s));
  EXPECT_FALSE(limiter.Blocked("10.0.0.2", t0 + 10s));  // another address is not
  EXPECT_TRUE(limiter.Blocked("10.0.0.1", t0 + 61s));   // the window runs from the last failure
  EXPECT_FALSE(limiter.Blocked("10.0.0.1", t0 + 63s));
}

}  // namespace
}  // namespace edsp::web
