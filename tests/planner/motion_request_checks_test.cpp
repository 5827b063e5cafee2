// A motion request's own checks, apart from the service's state: each
// refusal names the field and the value, and what passes is taken whole.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <string_view>

#include "edsp/planner/motion_request_checks.h"
#include "edsp/request_kinds.h"

namespace edsp {
namespace {

// The reason of a refusal ("" for none), for matching and printing.
std::string Why(const Problem& p) { return p.value_or(""); }

motion_request_t PoseRequest(double x, double z) {
  motion_request_t r{};
  r.pose[0] = x;
  r.pose[2] = z;
  return r;
}

MoveLimits ConfigLimits() {
  MoveLimits most;
  most.speed_m_s = 0.1;
  most.speed_rad_s = 0.2;
  most.accel_m_s2 = 0.5;
  most.accel_rad_s2 = 1.0;
  return most;
}

TEST(MotionRequestChecks, APoseMustBeFinite) {
  EXPECT_EQ(PoseProblem(PoseRequest(0.1, 1.5)), std::nullopt);
  EXPECT_NE(Why(PoseProblem(PoseRequest(std::nan(""), 1.5))).find("non-finite"), std::string::npos);
  EXPECT_NE(Why(PoseProblem(PoseRequest(0.0, std::numeric_limits<double>::infinity()))).find("non-finite"),
            std::string::npos);
  EXPECT_EQ(RequestPose(PoseRequest(0.1, 1.5))(2), 1.5);
}

TEST(MotionRequestChecks, AJogIsOneSmallFiniteStepAlongOneAxis) {
  motion_request_t r{};
  r.kind = motion_request_t::KIND_JOG;
  r.pose[0] = 0.01;  // 10 mm: the most
  EXPECT_EQ(JogProblem(r), std::nullopt);
  r.pose[0] = 0.0;
  r.pose[5] = -0.01;  // -10 mrad about yaw
  EXPECT_EQ(JogProblem(r), std::nullopt);
  r.pose[5] = 0.0;
  EXPECT_NE(Why(JogProblem(r)).find("zero"), std::string::npos) << Why(JogProblem(r));
  r.pose[1] = 0.002;
  r.pose[4] = 0.001;
  EXPECT_NE(Why(JogProblem(r)).find("along y, pitch: a jog moves along one axis"), std::string::npos)
      << Why(JogProblem(r));
  r = motion_request_t{};
  r.pose[2] = -0.0101;
  EXPECT_NE(Why(JogProblem(r)).find("along z = -0.0101 m is beyond 0.01 m"), std::string::npos) << Why(JogProblem(r));
  r.pose[2] = 0.0;
  r.pose[3] = 0.02;
  EXPECT_NE(Why(JogProblem(r)).find("along roll = 0.02 rad is beyond 0.01 rad"), std::string::npos)
      << Why(JogProblem(r));
  r.pose[3] = std::nan("");
  EXPECT_NE(Why(JogProblem(r)).find("along roll = nan: give a finite step"), std::string::npos) << Why(JogProblem(r));
  r.pose[3] = std::numeric_limits<double>::infinity();
  EXPECT_NE(Why(JogProblem(r)).find("finite"), std::string::npos) << Why(JogProblem(r));
  for (int k = 0; k < 6; ++k) EXPECT_EQ(JogAxisIndex(kJogAxes[k]), k);
  EXPECT_EQ(JogAxisIndex("rx"), -1);
}

TEST(MotionRequestChecks, AFrameNeedsANewNameAndAnOriginWithinReach) {
  motion_request_t r = PoseRequest(0.05, 1.55);
  r.frame = "fixture";
  EXPECT_EQ(FrameDefinitionProblem(r), std::nullopt);
  for (const char* built_in : {"", "base", "home"}) {
    r.frame = built_in;
    EXPECT_NE(Why(FrameDefinitionProblem(r)).find("base and home are built in"), std::string::npos) << built_in;
  }
  r.frame = "far";
  r.pose[0] = 100.5;
  EXPECT_NE(Why(FrameDefinitionProblem(r)).find("frame far: origin 100.5"), std::string::npos)
      << Why(FrameDefinitionProblem(r));
  r.pose[0] = std::nan("");
  EXPECT_NE(Why(FrameDefinitionProblem(r)).find("non-finite"), std::string::npos);
}

TEST(MotionRequestChecks, APivotMustBeFiniteAndWithinTenMetres) {
  motion_request_t r{};
  r.point[2] = 0.3;
  EXPECT_EQ(PivotProblem(r), std::nullopt);
  r.point[2] = 10.01;
  EXPECT_NE(Why(PivotProblem(r)).find("within 10 m"), std::string::npos);
  r.point[2] = std::nan("");
  EXPECT_NE(Why(PivotProblem(r)).find("finite"), std::string::npos);
}

TEST(MotionRequestChecks, AProgramIsNamedOrGivenAsCsvNotBoth) {
  motion_request_t r{};
  EXPECT_NE(ProgramProblem(r), std::nullopt);
  r.motions = "Lz";
  EXPECT_EQ(ProgramProblem(r), std::nullopt);
  r.csv_text = "t,x,y,z,roll,pitch,yaw\n";
  EXPECT_NE(ProgramProblem(r), std::nullopt);
}

TEST(MotionRequestChecks, LimitsAreTakenWithinTheConfigsAndZeroKeepsTheCurrent) {
  const MoveLimits most = ConfigLimits();
  MoveLimits current = most;
  current.speed_m_s = 0.05;
  motion_request_t r{};
  MoveLimits taken = current;
  EXPECT_EQ(SpeedLimitsProblem(r, most, &taken), std::nullopt);
  EXPECT_EQ(taken.speed_m_s, 0.05);  // 0 asked: the current one kept
  r.speed_m_s = 0.08;
  r.speed_rad_s = 0.1;
  EXPECT_EQ(SpeedLimitsProblem(r, most, &taken), std::nullopt);
  EXPECT_EQ(taken.speed_m_s, 0.08);
  EXPECT_EQ(taken.speed_rad_s, 0.1);
  r.speed_m_s = 0.2;  // above the config's
  EXPECT_NE(Why(SpeedLimitsProblem(r, most, &taken)).find("speed_m_s = 0.2 is not in [0.0001, 0.1]"), std::string::npos)
      << Why(SpeedLimitsProblem(r, most, &taken));
  r.speed_m_s = 0.5e-4;  // below a thousandth of it: a typo
  EXPECT_NE(SpeedLimitsProblem(r, most, &taken), std::nullopt);
  r = motion_request_t{};
  r.accel_rad_s2 = 2.0;
  taken = current;
  EXPECT_EQ(SpeedLimitsProblem(r, most, &taken), std::nullopt);  // a move's limits are speeds only
  EXPECT_NE(Why(AllLimitsProblem(r, most, &taken)).find("accel_rad_s2 = 2"), std::string::npos);
  r.accel_rad_s2 = 0.5;
  EXPECT_EQ(AllLimitsProblem(r, most, &taken), std::nullopt);
  EXPECT_EQ(taken.accel_rad_s2, 0.5);
}

TEST(MotionRequestChecks, EveryKindHasItsNameAndAnUnknownOneItsNumber) {
  EXPECT_EQ(RequestKindName(motion_request_t::KIND_MOVE), "move");
  EXPECT_EQ(RequestKindName(motion_request_t::KIND_LIMITS), "limits");
  EXPECT_EQ(RequestKindName(motion_request_t::KIND_DISENGAGE), "disengage");
  EXPECT_EQ(RequestKindName(motion_request_t::KIND_JOG), "jog");
  EXPECT_EQ(RequestKindName(42), "kind 42");
}

// One row per kind: a number or a name twice would make a client send one
// kind for another.
TEST(RequestKinds, EachKindAndEachNameIsInTheTableOnceAndFoundBothWays) {
  std::set<int> kinds;
  std::set<std::string> names;
  for (const RequestKindRow& row : kRequestKinds) {
    EXPECT_TRUE(kinds.insert(row.kind).second) << "kind " << int(row.kind) << " twice";
    EXPECT_TRUE(names.insert(std::string(row.name)).second) << row.name << " twice";
    EXPECT_EQ(FindRequestKind(row.kind), &row);
    EXPECT_EQ(FindRequestKind(row.name), &row);
  }
  EXPECT_EQ(FindRequestKind(std::int8_t{0}), nullptr);
  EXPECT_EQ(FindRequestKind(std::string_view("jump")), nullptr);
}

}  // namespace
}  // namespace edsp
