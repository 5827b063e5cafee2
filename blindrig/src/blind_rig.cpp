#include "edsp/blindrig/blind_rig.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <fmt/format.h>

namespace edsp::blind {

namespace {

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

void WriteHeader(bool encoders, bool corrections, std::string* csv) {
  *csv += "time_s,run";
  for (const char* a : {"x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"})
    *csv += fmt::format(",pose_cmd_{}", a);
  for (int i = 1; i <= 6; ++i) *csv += fmt::format(",leg_cmd_{}_m", i);
  if (encoders) {
    for (int i = 1; i <= 6; ++i) *csv += fmt::format(",leg_enc_{}_m", i);
  }
  if (corrections) {
    for (int i = 1; i <= 6; ++i) *csv += fmt::format(",leg_corr_{}_m", i);
  }
  *csv += ",point_x_m,point_y_m,point_z_m\n";
}

// The platform through one session of motions: the controller's commands,
// the drive trains, the true pose, and the tracker reading it.
class Session {
 public:
  Session(const BlindRigSetup& setup, const BlindEffects& e, const TrackerOptions& tracker)
      : setup_(setup),
        e_(e),
        tracker_(tracker),
        truth_(TrueGeometry(setup.geometry, e)),
        home_(HomePose(setup.geometry)),
        encoder_zero_(LegLengths(setup.geometry, home_)),
        nominal_home_twist_(LegBodyTwist(setup.geometry, home_)),
        true_home_twist_(LegBodyTwist(truth_, home_)),
        true_sign_(e.pr_override ? e.true_pr_sign : setup.pr_sign),
        tracker_R_(Rotation(tracker.frame)),
        tracker_t_(tracker.frame.head<3>()),
        moved_R_(Rotation(tracker.frame + e.change_tracker)),
        moved_t_((tracker.frame + e.change_tracker).head<3>()),
        draw_(tracker.seed),
        noise_(0.0, tracker.noise_m),
        floor_direction_(e.floor_direction.normalized()),
        q_true_(home_) {}

  // Appends the rows of one motion, sampled at the tracker's rate: each row
  // the controller's command and encoders at its stamp, and the tracker's
  // reading of the instant its clock puts it at (its offset, and what its
  // drift has added since the session began).
  void Run(const std::string& name, std::string* csv) {
    const BlindMotion motion = MotionNamed(setup_, name);
    ReseatTarget();
    const std::vector<Instant> instants = Simulate(motion);
    const double sample_period = 1.0 / tracker_.rate_hz;
    double next_sample_s = 0.0;
    for (const Instant& now : instants) {
      if (now.t + 1e-12 < next_sample_s) continue;
      next_sample_s += sample_period;
      const double late_s = tracker_.time_offset_s + e_.clock_drift * (session_s_ + now.t);
      const Instant read = At(instants, now.t - late_s);
      q_true_ = pose_solver_.Solve(
          [&](const Vec6& q) {
            return Vec6(LegLengths(truth_, q) -
                        PassiveRotation(truth_, q, true_home_twist_, true_sign_, setup_.lead_m) - read.lengths);
          },
          q_true_);
      AppendRow(session_s_ + now.t, name, now, Reading(TruePoint(read), session_s_ + now.t - late_s), csv);
    }
    session_s_ += motion.duration_s() + 1.0;
  }

 private:
  // The rig at one control step: what the controller commands and its
  // encoders read, and what the legs and the structure really do.
  struct Instant {
    double t = 0.0;
    Vec6 q_cmd, leg_cmd, correction = Vec6::Zero(), motor, lengths;
    Vec3 sway;
  };

  std::vector<Instant> Simulate(const BlindMotion& motion) {
    const double dt = 1.0 / setup_.control_rate_hz;
    const int steps = static_cast<int>(std::ceil(motion.duration_s() / dt));
    std::vector<Instant> out;
    out.reserve(static_cast<std::size_t>(steps) + 1);
    for (int k = 0; k <= steps; ++k) {
      Instant now;
      now.t = k * dt;
      now.q_cmd = motion.Pose(now.t);
      now.leg_cmd = ControllerCommand(now.q_cmd);
      if (setup_.calibration) {
        const Vec6 velocity = (motion.Pose(now.t + 0.5 * dt) - motion.Pose(now.t - 0.5 * dt)) / dt;
        now.correction =
            setup_.calibration(session_s_ + now.t, now.q_cmd, velocity, motion.Acceleration(now.t), now.leg_cmd);
        now.leg_cmd -= now.correction;
      }
      for (int i = 0; i < 6; ++i) {
        legs_[static_cast<std::size_t>(i)].Step(now.leg_cmd(i) - encoder_zero_(i), dt, e_, e_.backlash_m(i));
        now.motor(i) = encoder_zero_(i) + legs_[static_cast<std::size_t>(i)].motor;
      }
      sway_.Step(PointAcceleration(motion, setup_.geometry.point_M, now.t, dt), dt, e_);
      now.sway = sway_.x;
      now.lengths = TrueLengths(motion, now.q_cmd, now.t);
      out.push_back(now);
    }
    return out;
  }

  // The rig at time t of the motion, between control steps linearly; before
  // the motion it rests where it began, after it where it ended.
  Instant At(const std::vector<Instant>& instants, double t) const {
    const double u = std::clamp(t * setup_.control_rate_hz, 0.0, static_cast<double>(instants.size() - 1));
    const auto k = static_cast<std::size_t>(std::floor(u));
    const double w = u - static_cast<double>(k);
    if (w < 1e-9 || k + 1 >= instants.size()) return instants[std::min(k, instants.size() - 1)];
    if (w > 1.0 - 1e-9) return instants[k + 1];
    const Instant &a = instants[k], &b = instants[k + 1];
    Instant out;
    out.t = a.t + w * (b.t - a.t);
    out.q_cmd = a.q_cmd + w * (b.q_cmd - a.q_cmd);
    out.leg_cmd = a.leg_cmd + w * (b.leg_cmd - a.leg_cmd);
    out.correction = a.correction + w * (b.correction - a.correction);
    out.motor = a.motor + w * (b.motor - a.motor);
    out.lengths = a.lengths + w * (b.lengths - a.lengths);
    out.sway = a.sway + w * (b.sway - a.sway);
    return out;
  }

  // The controller: nominal IK, signed PR compensated with its s.
  Vec6 ControllerCommand(const Vec6& q_cmd) const {
    const BlindGeometry& nominal = setup_.geometry;
    return LegLengths(nominal, q_cmd) -
           PassiveRotation(nominal, q_cmd, nominal_home_twist_, setup_.pr_sign, setup_.lead_m);
  }

  // The legs' true lengths: drive trains, offsets, and the legs' give under load.
  Vec6 TrueLengths(const BlindMotion& motion, const Vec6& q_cmd, double t) const {
    Vec6 target = encoder_zero_ + e_.leg_offset_m;
    if (Changed(session_s_ + t) && e_.change_leg >= 0) target(e_.change_leg) += e_.change_m;
    for (int i = 0; i < 6; ++i) target(i) += legs_[static_cast<std::size_t>(i)].Extension(e_, i, setup_.lead_m);
    if (e_.mass_kg > 0.0 && e_.stiffness_N_m.minCoeff() > 0.0) {
      const Vec3 com_accel = motion.Acceleration(t).head<3>();
      target += LegTensions(truth_, q_cmd, e_.mass_kg, e_.com_M, com_accel).cwiseQuotient(e_.stiffness_N_m);
    }
    return target;
  }

  bool Changed(double session_time_s) const { return e_.change_time_s >= 0.0 && session_time_s >= e_.change_time_s; }

  // An operator takes the target out of its nest between runs and puts it
  // back: its centre lands a little apart each time (a nest's seat, a speck
  // of dust under the ball).
  void ReseatTarget() {
    if (e_.target_reseat_m <= 0.0) return;
    std::normal_distribution<double> seat(0.0, e_.target_reseat_m / std::sqrt(3.0));
    for (int a = 0; a < 3; ++a) target_offset_(a) = seat(reseat_draw_);
  }

  // Point A in {B} at the true pose, with the structure's sway and the base's tilt.
  Vec3 TruePoint(const Instant& at) const {
    Vec3 point = q_true_.head<3>() + Rotation(q_true_) * (setup_.geometry.point_M + target_offset_) + at.sway;
    if (e_.base_tilt_rad_per_N_m > 0.0) {
      const Vec3 com = at.q_cmd.head<3>() + Rotation(at.q_cmd) * e_.com_M;
      const Vec3 moment = com.cross(Vec3(0.0, 0.0, -kGravity * std::max(e_.mass_kg, 1.0)));
      const Vec3 tilt = e_.base_tilt_rad_per_N_m * moment;
      point = Eigen::AngleAxisd(tilt.norm(), tilt.norm() > 0.0 ? Vec3(tilt.normalized()) : Vec3::UnitZ()) * point;
    }
    return point;
  }

  // What the tracker reads: its frame, its stand's vibration and settling, its noise.
  Vec3 Reading(const Vec3& point, double time_s) {
    Vec3 measured = Changed(time_s) ? Vec3(moved_R_ * point + moved_t_) : Vec3(tracker_R_ * point + tracker_t_);
    measured += e_.floor_amplitude_m * std::sin(2.0 * kPi * e_.floor_hz * time_s) * floor_direction_;
    measured += e_.stand_drift_m_per_s * e_.stand_settle_s * (1.0 - std::exp(-time_s / e_.stand_settle_s));
    for (int a = 0; a < 3; ++a) measured(a) += noise_(draw_);
    return measured;
  }

  void AppendRow(double time_s, const std::string& name, const Instant& now, const Vec3& measured,
                 std::string* csv) const {
    *csv += fmt::format("{:.6f},{}", time_s, name);
    for (int a = 0; a < 6; ++a) *csv += fmt::format(",{:.9f}", now.q_cmd(a));
    for (int i = 0; i < 6; ++i) *csv += fmt::format(",{:.9f}", now.leg_cmd(i));
    if (tracker_.encoders) {
      for (int i = 0; i < 6; ++i) *csv += fmt::format(",{:.9f}", now.motor(i));
    }
    if (setup_.calibration) {
      for (int i = 0; i < 6; ++i) *csv += fmt::format(",{:.9f}", now.correction(i));
    }
    *csv += fmt::format(",{:.9f},{:.9f},{:.9f}\n", measured(0), measured(1), measured(2));
  }

  const BlindRigSetup& setup_;
  const BlindEffects& e_;
  const TrackerOptions& tracker_;
  const BlindGeometry truth_;
  const Vec6 home_, encoder_zero_, nominal_home_twist_, true_home_twist_;
  const int true_sign_;
  const Mat3 tracker_R_;
  const Vec3 tracker_t_;
  const Mat3 moved_R_;  // the tracker's frame after the session's change
  const Vec3 moved_t_;
  std::mt19937_64 draw_;
  std::normal_distribution<double> noise_;
  const Vec3 floor_direction_;
  std::array<LegDrive, 6> legs_;
  Sway sway_;
  Vec6 q_true_;
  PoseSolver pose_solver_;  // its Jacobian carried from one tracker sample to the next
  double session_s_ = 0.0;
  std::mt19937_64 reseat_draw_{tracker_.seed ^ 0x5ea7ULL};  // its own stream: the noise stays the same draw
  Vec3 target_offset_ = Vec3::Zero();  // where the target sits in {M} this run, from its nominal centre
};

}  // namespace

BlindMotion MotionNamed(const BlindRigSetup& setup, const std::string& name) {
  for (const SampledMotion& m : setup.sampled_motions) {
    if (m.name == name) return BlindMotion(m);
  }
  return BlindMotion(name, HomePose(setup.geometry), setup.limits);
}

std::string GenerateMeasurementCsv(const BlindRigSetup& setup, const BlindEffects& e, const TrackerOptions& tracker) {
  std::string csv = "# written by edsp-blind-rig (blindrig/): an independent virtual rig\n";
  WriteHeader(tracker.encoders, static_cast<bool>(setup.calibration), &csv);
  Session session(setup, e, tracker);
  for (const std::string& name : setup.motions) session.Run(name, &csv);
  return csv;
}

}  // namespace edsp::blind
