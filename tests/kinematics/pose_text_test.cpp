#include <gtest/gtest.h>

#include "thrown_message.h"

#include "edsp/kinematics/pose_text.h"

namespace edsp {
// Named, not anonymous: its helpers share names with other tests of its binary.
namespace pose_text {

TEST(PoseText, ParsesSixNumbersInOrder) {
  const Pose pose = ParsePoseText("0.1,-0.2,1.6,0.01,-2e-2,0.3");
  EXPECT_EQ(pose.ToVector(), (Vector6() << 0.1, -0.2, 1.6, 0.01, -0.02, 0.3).finished());
}

std::string ErrorOf(const std::string& text) {
  return test_support::ThrownMessage<std::invalid_argument>([&] { ParsePoseText(text); });
}

TEST(PoseText, RejectsWhatIsNotSixFiniteNumbers) {
  EXPECT_NE(ErrorOf("0,0,1.5,0,0").find("exactly six"), std::string::npos);
  EXPECT_NE(ErrorOf("0,0,1.5,0,0,0,0").find("exactly six"), std::string::npos);
  EXPECT_NE(ErrorOf("0,0,1.5,0,0,").find("yaw"), std::string::npos);
  EXPECT_NE(ErrorOf("0,0,1.5,nan,0,0").find("roll = \"nan\""), std::string::npos);
  EXPECT_NE(ErrorOf("0,0,inf,0,0,0").find("z = \"inf\""), std::string::npos);
  EXPECT_NE(ErrorOf("0,0,1.5m,0,0,0").find("z = \"1.5m\""), std::string::npos);
  EXPECT_NE(ErrorOf("").find("exactly six"), std::string::npos);
}

}  // namespace pose_text
}  // namespace edsp

namespace edsp {
namespace {

TEST(PointText, ThreeFiniteNumbersOrTheFieldNamed) {
  EXPECT_EQ(ParsePointText("0,-0.5,0.3"), Vector3(0.0, -0.5, 0.3));
  for (const char* bad : {"0,0", "0,0,0,0", "0,x,0", "0,0,nan"})
    EXPECT_THROW(ParsePointText(bad), std::invalid_argument) << bad;
}

TEST(RpyFromRotation, InvertsRotationFromRpyAwayFromGimbalLock) {
  for (const Vector3& rpy : {Vector3(0.1, -0.2, 0.3), Vector3(-1.0, 1.2, 3.0), Vector3(0.0, 0.0, 0.0)}) {
    EXPECT_LT((RpyFromRotation(RotationFromRpy(rpy)) - rpy).norm(), 1e-12) << rpy.transpose();
  }
}

}  // namespace
}  // namespace edsp
