#pragma once
// The leg forces of a rigid platform (the compliance effect's loads, for the
// rig, the diagnosis and the calibration alike): the six
// legs hold the platform and its payload against gravity and accelerate it.
// Quasi-static: the centre of mass's acceleration is given, rotational
// inertia is neglected (small next to gravity at the rates a rig moves).

#include "edsp/kinematics/platform_model.h"

namespace edsp {

// Force each leg exerts on the platform along its axis (base → platform
// joint), N: positive pushes, i.e. the leg is in compression. Solves
// Jᵀ f = [m (a − g); r × m (a − g)] with J the geometric (twist) Jacobian and
// r the centre of mass from {M}'s origin, in {B}.
Vector6 LegForces(const PlatformModel& model, const Pose& X_BM, const Vector3& accel_B_m_s2, double mass_kg,
                  const Vector3& com_M_m, const Vector3& gravity_B_m_s2);

}  // namespace edsp
