// The columns the diagnosis puts beside its effects for structure outside
// the vocabulary, against the physics they stand for, computed another way.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "edsp/diagnosis/structure_nuisance.h"
#include "edsp/kinematics/config.h"
#include "random_pose_rows.h"
#include "platform_models.h"

namespace edsp::gap {
namespace {

// A payload of mass m with its c.o.m. at c in {M}, on a base that turns by
// θ = C·M about {B}'s origin under the moment M of the payload's weight:
// the platform, and A with it, turns with the base.
struct TiltingBase {
  double mass_kg = 600.0;
  Vector3 com_M = Vector3(0.05, -0.08, 0.2);
  Matrix3 compliance_rad_per_N_m;
  Vector3 Moved(const Pose& pose, const Vector3& A_B) const {
    const Vector3 com_B = pose.p_BoMo_B + RotationFromRpy(pose.rpy_rad) * com_M;
    const Vector3 moment = com_B.cross(Vector3(0.0, 0.0, -9.81 * mass_kg));
    const Vector3 theta = compliance_rad_per_N_m * moment;
    return Eigen::AngleAxisd(theta.norm(), theta.normalized()) * A_B;
  }
};

// Rows at poses far apart in time (the platform at rest: its weight alone
// loads the base), measured exactly in a tracker frame, with the base tilting.
MeasurementData TiltedData(const PlatformModel& model, const Pose& X_TB, const TiltingBase& base, int rows) {
  return RandomPoseRows(model, X_TB, rows, PrMode::kSigned, 0.1, 100.0, 11,
                        [&](const Pose& pose, const Vector3& A) { return base.Moved(pose, A); });
}

TEST(StructureNuisance, BaseTiltColumnsAreTheBaseTurningUnderThePayloadsWeight) {
  const PlatformModel model = test_support::Huang2021Model();
  Pose X_TB;
  X_TB.p_BoMo_B = Vector3(2.0, -1.5, 0.3);
  X_TB.rpy_rad = Vector3(0.01, -0.02, 2.5);
  TiltingBase base;
  base.compliance_rad_per_N_m << 2.0, 0.5, 0.1, 0.5, 3.0, -0.2, 0.1, -0.2, 1.0;
  base.compliance_rad_per_N_m *= 1e-8;
  // The tilt as the tracker sees it: the tilted points less the level ones.
  // The design's frame R0 is estimated from the tilted points, within
  // ~1e-5 rad of the true one, which the tolerances below allow.
  const MeasurementData measured = TiltedData(model, X_TB, base, 90);
  const Design tilted = BuildDesign(model, measured);
  TiltingBase level = base;
  level.compliance_rad_per_N_m.setZero();
  const MeasurementData untilted = TiltedData(model, X_TB, level, 90);
  Eigen::VectorXd motion(3 * tilted.samples());
  for (int k = 0; k < tilted.samples(); ++k) {
    const std::size_t row = static_cast<std::size_t>(tilted.source_row[static_cast<std::size_t>(k)]);
    motion.segment<3>(3 * k) = measured.rows[row].point_m - untilted.rows[row].point_m;
  }
  ASSERT_GT(motion.cwiseAbs().maxCoeff(), 5e-6);  // a tilt worth detecting

  const Eigen::MatrixXd columns = BaseTiltColumns(tilted);
  ASSERT_EQ(columns.cols(), 24);
  const Eigen::VectorXd terms = columns.colPivHouseholderQr().solve(motion);
  EXPECT_LT((columns * terms - motion).norm(), 1e-4 * motion.norm());
  // The terms are C·m, then C·m·c along {M}'s x, y, z (upper triangle, by rows).
  const double scale[4] = {1.0, base.com_M.x(), base.com_M.y(), base.com_M.z()};
  for (int block = 0, t = 0; block < 4; ++block) {
    for (int i = 0; i < 3; ++i) {
      for (int j = i; j < 3; ++j, ++t) {
        if (i == 2 && j == 2) continue;  // a weight has no moment about the vertical: C_zz unseen at rest
        const double expected = base.mass_kg * scale[block] * base.compliance_rad_per_N_m(i, j);
        EXPECT_NEAR(terms(t), expected, 1e-3 * base.mass_kg * 3e-8) << "term " << t;
      }
    }
  }
}

}  // namespace
}  // namespace edsp::gap
