// edsp-log faults, as deploy/edsp calibrate and users' scripts call it: the
// faults of chosen nodes and codes (by number or name), counted, and a code
// it does not know refused by name.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "edsp/channels.h"
#include "edsp/node/fault.h"
#include "scratch_dir.h"
#include "edsp/node/build_paths.h"

namespace edsp {
namespace {

struct CliRun {
  int status;
  std::string out;
};

CliRun EdspLog(const std::string& args) {
  CliRun run{-1, {}};
  FILE* pipe = popen((BuiltProgram("edsp-log") + " " + args + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe) != nullptr) run.out += buffer;
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

void WriteFault(lcm::LogFile* log, const fault_t& f) {
  fault_t copy = f;
  std::string bytes(static_cast<std::size_t>(copy.getEncodedSize()), '\0');
  copy.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  lcm::LogEvent event{};
  event.timestamp = f.utime;
  event.channel = channel::kFault;
  event.datalen = static_cast<int32_t>(bytes.size());
  event.data = bytes.data();
  ASSERT_EQ(log->writeEvent(&event), 0);
}

// Three faults: the bridge latched, the bridge refused a stale stamp (no
// hold), the rig lost the platform's pose.
std::string LogWithThreeFaults() {
  const std::string path = test_support::ScratchDir("edsp_log_faults") + "/faults.lcmlog";
  lcm::LogFile log(path, "w");
  WriteFault(&log, MakeFault("actuator_bridge", channel::kLegCommand, FaultCode::kLatched, fault_t::SEVERITY_ERROR,
                             "no valid leg command for 60000 us: holding", 1000000));
  WriteFault(&log, MakeFault("actuator_bridge", channel::kLegCommand, FaultCode::kStale, fault_t::SEVERITY_WARNING,
                             "leg command seq 7 is 80000 us old", 2000000));
  WriteFault(&log, MakeFault("rig", "", FaultCode::kForwardKinematics, fault_t::SEVERITY_ERROR,
                             "the virtual platform's pose could not be found", 3000000));
  return path;
}

TEST(EdspLogFaults, ListsOnlyTheNodesAndCodesAskedFor) {
  const std::string log = LogWithThreeFaults();
  const CliRun all = EdspLog("faults " + log);
  EXPECT_EQ(all.status, 0) << all.out;
  EXPECT_NE(all.out.find("\n3 faults\n"), std::string::npos) << all.out;

  const CliRun latched = EdspLog("faults " + log + " --node actuator_bridge --code latched");
  EXPECT_EQ(latched.status, 0) << latched.out;
  EXPECT_NE(latched.out.find("code 16 (latched)"), std::string::npos) << latched.out;
  EXPECT_EQ(latched.out.find("80000 us old"), std::string::npos) << "a stale stamp is no hold:\n" << latched.out;
  EXPECT_NE(latched.out.find("\n1 faults\n"), std::string::npos) << latched.out;

  const CliRun by_number = EdspLog("faults " + log + " --code 16,8");
  EXPECT_NE(by_number.out.find("\n2 faults\n"), std::string::npos) << by_number.out;
  const CliRun of_rig = EdspLog("faults " + log + " --node rig --code forward_kinematics,latched");
  EXPECT_NE(of_rig.out.find("pose could not be found"), std::string::npos) << of_rig.out;
  EXPECT_NE(of_rig.out.find("\n1 faults\n"), std::string::npos) << of_rig.out;
}

TEST(EdspLogFaults, ACodeItDoesNotKnowIsRefusedByName) {
  const CliRun run = EdspLog("faults " + LogWithThreeFaults() + " --code lached");
  EXPECT_NE(run.status, 0) << run.out;
  EXPECT_NE(run.out.find("--code lached: no such fault code"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace edsp
