// lcm-spy as users start it (deploy/edsp-spy: Java 17, the edsp jar on the
// classpath) under Xvfb, in this test's private network namespace, while
// edsp messages are published: it decodes every edsp channel as its edsp type
// with no undecodable message, and its last decoded message is the last sent.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "edsp/leg_command_t.hpp"
#include "edsp/pose_setpoint_t.hpp"
#include "edsp/transport/bus.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

struct SpyRow {
  std::string type;
  long received = 0, undecodable = 0;
  std::string last_seq;
};

std::map<std::string, SpyRow> ParseProbe(const std::string& path) {
  std::map<std::string, SpyRow> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream cells(line);
    std::string channel;
    SpyRow row;
    if (std::getline(cells, channel, '\t') && std::getline(cells, row.type, '\t') &&
        (cells >> row.received >> row.undecodable >> row.last_seq)) {
      rows[channel] = row;
    }
  }
  return rows;
}

TEST(LcmSpy, DecodesEdspMessagesOnJava17UnderXvfb) {
  const std::string dir = test_support::ScratchDir("spy_test");
  std::system(("mkdir -p " + dir).c_str());
  const std::string url = "udpm://239.255.76.67:7667?ttl=0";
  // Xvfb on a display it finds free, which it names once it accepts
  // clients (-displayfd; 60 s at most), then the probe (the real
  // lcm.spy.Spy) watching for 5 s.
  const std::string script = fmt::format(
      "Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>{0}/xvfb.display >{0}/xvfb.log 2>&1 & X=$!; "
      "for i in $(seq 600); do grep -q . {0}/xvfb.display && break; kill -0 $X 2>/dev/null || break; sleep 0.1; done; "
      "D=$(head -n1 {0}/xvfb.display); "
      "[ -n \"$D\" ] || {{ kill $X; echo 'Xvfb named no display' >{0}/probe.err; exit 3; }}; "
      "DISPLAY=:$D EDSP_BUILD_DIR={1} EDSP_SPY_MAIN=SpyProbe EDSP_SPY_EXTRA_CP={2} "
      "{3}/deploy/edsp-spy --lcm-url='{4}' 5 {0}/spy.ready >{0}/probe.out 2>>{0}/probe.err; S=$?; kill $X; exit $S",
      dir, BuildPath("."), BuildPath("tests/deploy/spy_probe.jar"), SourceDir(), url);
  int status = -1;
  std::thread spy([&] { status = std::system(script.c_str()); });
  TransportConfig config;
  config.lcm_url = url;
  Bus bus(config);
  auto setpoints = bus.Advertise<pose_setpoint_t>("EDSP_SETPOINT");
  auto commands = bus.Advertise<leg_command_t>("EDSP_LEG_COMMAND");
  std::int64_t seq = 0, seq_at_ready = -1;
  // 100 Hz from before the spy starts until 3 s after it is up (it watches
  // 5 s from then, so its last message is our last); 60 s at most.
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  auto until = give_up;
  while (std::chrono::steady_clock::now() < until) {
    if (until == give_up && ::access((dir + "/spy.ready").c_str(), F_OK) == 0) {
      until = std::chrono::steady_clock::now() + std::chrono::seconds(3);
      seq_at_ready = seq;
    }
    pose_setpoint_t sp{};
    sp.seq = ++seq;
    sp.pose[2] = 1.511;
    sp.trajectory = "Lz/move 1";
    setpoints.Publish(sp);
    leg_command_t c{};
    c.seq = seq;
    c.pr_mode = leg_command_t::PR_SIGNED;
    commands.Publish(c);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::int64_t last_sent = seq;
  spy.join();
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
      << "the probe failed; see " << dir << "/probe.err and xvfb.log";
  const auto rows = ParseProbe(dir + "/probe.out");
  for (const auto& [channel, type] : std::map<std::string, std::string>{{"EDSP_SETPOINT", "edsp.pose_setpoint_t"},
                                                                        {"EDSP_LEG_COMMAND", "edsp.leg_command_t"}}) {
    ASSERT_EQ(rows.count(channel), 1u) << channel << " not seen by lcm-spy; " << dir << "/probe.out";
    const SpyRow& r = rows.at(channel);
    EXPECT_EQ(r.type, type) << channel;
    // At least what was sent once the spy was up (3 s at up to 100 Hz).
    EXPECT_GE(r.received, last_sent - seq_at_ready) << channel;
    EXPECT_EQ(r.undecodable, 0) << channel;
    // The spy outlives the publisher by ~2 s: its last message is our last.
    EXPECT_EQ(r.last_seq, std::to_string(last_sent)) << channel;
  }
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace edsp
