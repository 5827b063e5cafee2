#include "edsp/blindrig/blind_rig.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

namespace edsp::blind {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.81;

double Wrap(double angle) { return std::remainder(angle, 2.0 * kPi); }

BlindGeometry TrueGeometry(const BlindGeometry& nominal, const BlindEffects& e) {
  BlindGeometry g = nominal;
  g.base_joint += e.base_joint_error_m;
  g.platform_joint += e.platform_joint_error_m;
  return g;
}

// Screw length change from the twist of the leg bodies since home (PR).
Vec6 PassiveRotation(const BlindGeometry& g, const Vec6& q, const Vec6& home_twist, int sign, double lead) {
  const Vec6 twist = LegBodyTwist(g, q);
  Vec6 e;
  for (int i = 0; i < 6; ++i) e(i) = sign * Wrap(twist(i) - home_twist(i)) / (2.0 * kPi) * lead;
  return e;
}

// Leg tensions holding the platform (mass, centre of mass in {M}) at pose q
// with the centre of mass accelerating at `accel`: Σ tᵢuᵢ = m(g − a) and
// Σ tᵢ(Pᵢ × uᵢ) = c × m(g − a), all in {B}; rotational inertia neglected.
Vec6 LegTensions(const BlindGeometry& g, const Vec6& q, double mass, const Vec3& com_M, const Vec3& accel) {
  const Mat3 R = Rotation(q);
  Eigen::Matrix<double, 6, 6> A;
  for (int i = 0; i < 6; ++i) {
    const Vec3 u = LegVector(g, q, i).normalized();
    const Vec3 P = q.head<3>() + R * g.platform_joint.col(i);
    A.col(i) << u, P.cross(u);
  }
  const Vec3 load = mass * (Vec3(0.0, 0.0, -kGravity) - accel);
  const Vec3 c = q.head<3>() + R * com_M;
  Vec6 w;
  w << load, c.cross(load);
  return A.partialPivLu().solve(w);
}

// One leg's drive train: motor loop, play, screw, heat.
struct LegDrive {
  double motor = 0.0, motor_speed = 0.0;  // travel units (m)
  double screw = 0.0;                     // after the play
  double temperature_K = 0.0;             // above ambient

  void Step(double target, double dt, const BlindEffects& e, double backlash) {
    if (e.servo_bandwidth_hz > 0.0) {
      const double w = 2.0 * kPi * e.servo_bandwidth_hz;
      constexpr int kSubsteps = 8;
      const double h = dt / kSubsteps;
      for (int k = 0; k < kSubsteps; ++k) {
        motor_speed += h * (w * w * (target - motor) - 2.0 * w * motor_speed);
        motor += h * motor_speed;
      }
    } else {
      motor_speed = (target - motor) / dt;
      motor = target;
    }
    const double before = screw;
    if (motor - screw > backlash / 2.0) screw = motor - backlash / 2.0;
    if (motor - screw < -backlash / 2.0) screw = motor + backlash / 2.0;
    const double heat = e.heating_K_per_m * std::abs(screw - before) + e.heating_K_per_s * dt;
    temperature_K += heat - temperature_K * dt / e.thermal_tau_s;
  }

  // Leg length beyond its length at encoder zero.
  double Extension(const BlindEffects& e, int leg, double lead) const {
    return screw * (1.0 + e.lead_error(leg)) +
           e.periodic_amplitude_m(leg) * std::sin(2.0 * kPi * screw / lead + e.periodic_phase_rad(leg)) +
           e.alpha_per_K * temperature_K * (0.5 * e.screw_length_m + screw);
  }
};

// A lightly damped mode per axis driven by the acceleration of A.
struct Sway {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
  void Step(const Vec3& accel, double dt, const BlindEffects& e) {
    if (e.resonance_hz <= 0.0) return;
    const double w = 2.0 * kPi * e.resonance_hz;
    constexpr int kSubsteps = 8;
    const double h = dt / kSubsteps;
    for (int k = 0; k < kSubsteps; ++k) {
      v += h * (-e.resonance_gain * accel - w * w * x - 2.0 * e.resonance_damping * w * v);
      x += h * v;
    }
  }
};

Vec3 PointAcceleration(const BlindMotion& motion, const Vec3& point_M, double t, double dt) {
  const auto at = [&](double s) {
    const Vec6 q = motion.Pose(s);
    return Vec3(q.head<3>() + Rotation(q) * point_M);
  };
  return (at(t + dt) - 2.0 * at(t) + at(t - dt)) / (dt * dt);
}

void WriteHeader(bool encoders, std::string* csv) {
  *csv += "time_s,run";
  for (const char* a : {"x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"}) *csv += fmt::format(",pose_cmd_{}", a);
  for (int i = 1; i <= 6; ++i) *csv += fmt::format(",leg_cmd_{}_m", i);
  if (encoders) {
    for (int i = 1; i <= 6; ++i) *csv += fmt::format(",leg_enc_{}_m", i);
  }
  *csv += ",point_x_m,point_y_m,point_z_m\n";
}

}  // namespace

std::string GenerateMeasurementCsv(const BlindRigSetup& setup, const BlindEffects& e, const TrackerOptions& tracker) {
  const BlindGeometry& nominal = setup.geometry;
  const BlindGeometry truth = TrueGeometry(nominal, e);
  const Vec6 home = HomePose(nominal);
  const Vec6 encoder_zero = LegLengths(nominal, home);
  const Vec6 nominal_home_twist = LegBodyTwist(nominal, home), true_home_twist = LegBodyTwist(truth, home);
  const int true_sign = e.pr_override ? e.true_pr_sign : setup.pr_sign;
  const Mat3 tracker_R = Rotation(tracker.frame);
  const Vec3 tracker_t = tracker.frame.head<3>();
  std::mt19937_64 draw(tracker.seed);
  std::normal_distribution<double> noise(0.0, tracker.noise_m);
  const Vec3 floor_direction = e.floor_direction.normalized();

  std::string csv = "# written by edsp-blind-rig (blindrig/): an independent virtual rig\n";
  WriteHeader(tracker.encoders, &csv);
  const double dt = 1.0 / setup.control_rate_hz, sample_period = 1.0 / tracker.rate_hz;
  std::array<LegDrive, 6> legs;
  Sway sway;
  Vec6 q_true = home;
  double session_s = 0.0;
  for (const std::string& name : setup.motions) {
    const BlindMotion motion(name, home, setup.limits);
    const int steps = static_cast<int>(std::ceil(motion.duration_s() / dt));
    double next_sample_s = 0.0;
    for (int k = 0; k <= steps; ++k) {
      const double t = k * dt;
      const Vec6 q_cmd = motion.Pose(t);
      // The controller: nominal IK, signed PR compensated with its s.
      const Vec6 leg_cmd = LegLengths(nominal, q_cmd) -
                           PassiveRotation(nominal, q_cmd, nominal_home_twist, setup.pr_sign, setup.lead_m);
      const Vec3 point_accel = PointAcceleration(motion, nominal.point_M, t, dt);
      for (int i = 0; i < 6; ++i) legs[static_cast<std::size_t>(i)].Step(leg_cmd(i) - encoder_zero(i), dt, e, e.backlash_m(i));
      sway.Step(point_accel, dt, e);
      if (t + 1e-12 < next_sample_s) continue;
      next_sample_s += sample_period;

      Vec6 target = encoder_zero + e.leg_offset_m;
      for (int i = 0; i < 6; ++i) target(i) += legs[static_cast<std::size_t>(i)].Extension(e, i, setup.lead_m);
      if (e.mass_kg > 0.0 && e.stiffness_N_m.minCoeff() > 0.0) {
        const Vec3 com_accel = motion.Acceleration(t).head<3>();
        target += LegTensions(truth, q_cmd, e.mass_kg, e.com_M, com_accel).cwiseQuotient(e.stiffness_N_m);
      }
      q_true = SolvePose(
          [&](const Vec6& q) {
            return Vec6(LegLengths(truth, q) - PassiveRotation(truth, q, true_home_twist, true_sign, setup.lead_m) -
                        target);
          },
          q_true);
      Vec3 point = q_true.head<3>() + Rotation(q_true) * nominal.point_M + sway.x;
      if (e.base_tilt_rad_per_N_m > 0.0) {
        const Vec3 com = q_cmd.head<3>() + Rotation(q_cmd) * e.com_M;
        const Vec3 moment = com.cross(Vec3(0.0, 0.0, -kGravity * std::max(e.mass_kg, 1.0)));
        const Vec3 tilt = e.base_tilt_rad_per_N_m * moment;
        point = Eigen::AngleAxisd(tilt.norm(), tilt.norm() > 0.0 ? Vec3(tilt.normalized()) : Vec3::UnitZ()) * point;
      }
      const double time_s = session_s + t;
      Vec3 measured = tracker_R * point + tracker_t;
      measured += e.floor_amplitude_m * std::sin(2.0 * kPi * e.floor_hz * time_s) * floor_direction;
      for (int a = 0; a < 3; ++a) measured(a) += noise(draw);

      csv += fmt::format("{:.6f},{}", time_s, name);
      for (int a = 0; a < 6; ++a) csv += fmt::format(",{:.9f}", q_cmd(a));
      for (int i = 0; i < 6; ++i) csv += fmt::format(",{:.9f}", leg_cmd(i));
      if (tracker.encoders) {
        for (int i = 0; i < 6; ++i) csv += fmt::format(",{:.9f}", encoder_zero(i) + legs[static_cast<std::size_t>(i)].motor);
      }
      csv += fmt::format(",{:.9f},{:.9f},{:.9f}\n", measured(0), measured(1), measured(2));
    }
    session_s += motion.duration_s() + 1.0;
  }
  return csv;
}

}  // namespace edsp::blind
