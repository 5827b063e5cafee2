#include "edsp/kinematics/platform_loads.h"

#include <Eigen/LU>

namespace edsp {

Vector6 LegForces(const PlatformModel& model, const Pose& X_BM, const Vector3& accel_B_m_s2, double mass_kg,
                  const Vector3& com_M_m, const Vector3& gravity_B_m_s2) {
  const Matrix6 J = model.TwistJacobian(X_BM);                      // rows [uᵢᵀ, (R pᵢ × uᵢ)ᵀ]
  const Vector3 force = mass_kg * (accel_B_m_s2 - gravity_B_m_s2);  // what the legs must supply
  const Vector3 r = RotationFromRpy(X_BM.rpy_rad) * com_M_m;
  Vector6 wrench;
  wrench << force, r.cross(force);
  return J.transpose().lu().solve(wrench);
}

}  // namespace edsp
