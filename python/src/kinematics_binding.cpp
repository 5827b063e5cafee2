// edsp.Kinematics: inverse and forward kinematics, the PR twist and the
// corrections the kinematics node subtracts (PR and a calibration), over
// (N, 6) numpy arrays, each loop run with the GIL released.
#include <pybind11/stl.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bindings.h"
#include "edsp/kinematics/calibration.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/kinematics/workspace.h"

namespace edsp::python {

namespace {

using Times = py::array_t<double, py::array::c_style | py::array::forcecast>;

// `times_s` for `rows` poses: strictly increasing finite seconds, or a
// ValueError naming the first that is not.
Times CheckedTimes(const py::handle& value, py::ssize_t rows) {
  const Times times = Times::ensure(value);
  if (!times || times.ndim() != 1 || times.shape(0) != rows) {
    throw py::value_error(fmt::format("times_s: want {} times (one per pose, shape ({},))", rows, rows));
  }
  const double* t = times.data();
  for (py::ssize_t i = 0; i < rows; ++i) {
    if (!std::isfinite(t[i])) throw py::value_error(fmt::format("times_s: row {} is {} (must be finite)", i, t[i]));
    if (i > 0 && !(t[i] > t[i - 1])) {
      throw py::value_error(
          fmt::format("times_s: row {} ({} s) does not come after row {} ({} s)", i, t[i], i - 1, t[i - 1]));
    }
  }
  return times;
}

// Row b − row a, the angles' differences wrapped (a yaw through ±π is a small step).
Vector6 Step(const double* q, py::ssize_t a, py::ssize_t b) {
  Vector6 d = Eigen::Map<const Vector6>(q + 6 * b) - Eigen::Map<const Vector6>(q + 6 * a);
  for (int k = 3; k < 6; ++k) d(k) = WrapAngle(d(k));
  return d;
}

// The pose's rates at row i of a sampled trajectory: the three-point
// differences, second order on unevenly spaced samples too (one-sided at
// the ends, where the acceleration is taken as 0).
void Rates(const double* q, const double* t, py::ssize_t n, py::ssize_t i, Vector6* velocity, Vector6* accel) {
  velocity->setZero(), accel->setZero();
  if (n < 2) return;
  if (i == 0 || i == n - 1) {
    const py::ssize_t a = i == 0 ? 0 : n - 2;
    *velocity = Step(q, a, a + 1) / (t[a + 1] - t[a]);
    return;
  }
  const double h1 = t[i] - t[i - 1], h2 = t[i + 1] - t[i];
  const Vector6 ahead = Step(q, i, i + 1), behind = Step(q, i - 1, i);
  *velocity = (h1 * h1 * ahead + h2 * h2 * behind) / (h1 * h2 * (h1 + h2));
  *accel = 2.0 * (ahead / h2 - behind / h1) / (h1 + h2);
}

// out[i] = f(pose i) for every row, the GIL released while it runs.
template <typename F>
py::array_t<double> EachPose(const Rows& poses, F f) {
  const py::ssize_t n = poses.shape(0);
  py::array_t<double> out({n, py::ssize_t{6}});
  const double* q = poses.data();
  double* rows = out.mutable_data();
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) {
      Eigen::Map<Vector6>(rows + 6 * i) = f(i, Pose::FromVector(Eigen::Map<const Vector6>(q + 6 * i)));
    }
  }
  return out;
}

class Kinematics {
 public:
  Kinematics(const std::string& config_path, const std::string& calibration_path, bool apply_ambiguous)
      : model_(LoadConfigFile(config_path)) {
    if (!calibration_path.empty())
      calibration_ = calibration::LoadCalibration(calibration_path, model_, apply_ambiguous);
  }

  // What the command subtracts from each pose's IK lengths: the PR length
  // error `pr_mode` predicts, and the calibration's correction (with
  // `times_s`, the rows as a trajectory followed by one compensator; without,
  // each pose at rest on its own).
  py::array_t<double> Compensate(const py::handle& poses_in, const std::string& pr_mode,
                                 const py::handle& times_in) const {
    const Rows poses = SixColumns(poses_in, "poses");
    const PrMode mode = ModeOf(pr_mode);
    const py::ssize_t n = poses.shape(0);
    const std::optional<Times> times =
        times_in.is_none() ? std::nullopt : std::optional<Times>(CheckedTimes(times_in, n));
    const double* q = poses.data();
    const double* t = times ? times->data() : nullptr;
    std::optional<calibration::LegCompensator> along;  // the trajectory's, with times
    return EachPose(poses, [&](py::ssize_t i, const Pose& pose) {
      const Vector6 pr = model_.PrLengthError(pose, mode);
      if (!calibration_) return pr;
      const Vector6 command = model_.LegLengths(pose) - pr;
      if (t == nullptr) return Vector6(pr + AtRest(pose, command));
      Vector6 velocity, accel;
      Rates(q, t, n, i, &velocity, &accel);
      if (!along) along.emplace(model_, *calibration_);
      return Vector6(pr + along->Step(t[i], pose, velocity, accel, command).command_m);
    });
  }

  // The leg lengths to command for each pose: IK − Compensate.
  py::array_t<double> Ik(const py::handle& poses_in, const std::string& pr_mode, const py::handle& times_in) const {
    const Rows poses = SixColumns(poses_in, "poses");
    const PrMode mode = ModeOf(pr_mode);
    if (calibration_) {
      const py::array_t<double> corrections = Compensate(poses, pr_mode, times_in);
      const double* c = corrections.data();
      return EachPose(poses, [&](py::ssize_t i, const Pose& pose) {
        return Vector6(model_.LegLengths(pose) - Eigen::Map<const Vector6>(c + 6 * i));
      });
    }
    if (!times_in.is_none()) CheckedTimes(times_in, poses.shape(0));  // named even where unused
    // The node's own one-pass formula (the fast path).
    return EachPose(poses, [&](py::ssize_t, const Pose& pose) { return model_.CompensatedLengths(pose, mode); });
  }

  // The signed twist of every leg's screw (rad) at each pose.
  py::array_t<double> PrTwist(const py::handle& poses_in) const {
    return EachPose(SixColumns(poses_in, "poses"),
                    [&](py::ssize_t, const Pose& pose) { return Vector6(model_.Solve(pose).twist_rad); });
  }

  // The pose for each row of leg lengths (those IK commands for `pr_mode`);
  // a row that does not converge raises, naming it and why.
  py::array_t<double> Fk(const py::handle& lengths_in, bool with_pr) const {
    const Rows lengths = SixColumns(lengths_in, "lengths");
    const py::ssize_t n = lengths.shape(0);
    py::array_t<double> out({n, py::ssize_t{6}});
    const double* in = lengths.data();
    double* poses = out.mutable_data();
    std::string failure;
    {
      py::gil_scoped_release release;
      FkOptions options;
      options.with_pr = with_pr;
      Pose guess = model_.home_pose();
      for (py::ssize_t i = 0; i < n && failure.empty(); ++i) {
        const FkResult r = SolveForward(model_, Eigen::Map<const Vector6>(in + 6 * i), guess, options);
        if (!r.ok()) {
          failure = fmt::format("lengths row {}: forward kinematics {} (residual {:.3g} m)", i, FkStatusName(r.status),
                                r.residual_m);
          break;
        }
        Eigen::Map<Vector6>(poses + 6 * i) = r.pose.ToVector();
        guess = r.pose;  // rows are usually a trajectory: start from the last
      }
    }
    if (!failure.empty()) throw py::value_error(failure);
    return out;
  }

  // None for a pose inside the workspace, else what limit it crosses.
  std::vector<std::optional<std::string>> Check(const py::handle& poses_in) const {
    const Rows poses = SixColumns(poses_in, "poses");
    std::vector<std::optional<std::string>> out;
    for (py::ssize_t i = 0; i < poses.shape(0); ++i) {
      const WorkspaceCheck c =
          CheckWorkspace(model_, Pose::FromVector(Eigen::Map<const Vector6>(poses.data() + 6 * i)));
      out.push_back(c.ok() ? std::nullopt : std::optional<std::string>(c.Describe()));
    }
    return out;
  }

  py::array_t<double> Home() const {
    py::array_t<double> out(py::ssize_t{6});
    Eigen::Map<Vector6>(out.mutable_data()) = model_.home_pose().ToVector();
    return out;
  }

  // The calibration in force: what it applies and what not; "" for none.
  std::string CalibrationText() const { return calibration_ ? calibration_->Describe() : ""; }

 private:
  // The calibration's correction of a pose held at rest (a compensator of its own: no history).
  Vector6 AtRest(const Pose& pose, const Vector6& command) const {
    calibration::LegCompensator compensator(model_, *calibration_);
    return compensator.Step(0.0, pose, Vector6::Zero(), Vector6::Zero(), command).command_m;
  }

  PlatformModel model_;
  std::optional<calibration::CalibrationModel> calibration_;
};

}  // namespace

void BindKinematics(py::module_& m) {
  py::class_<Kinematics>(m, "Kinematics")
      .def(py::init<const std::string&, const std::string&, bool>(), py::arg("config"), py::arg("calibration"),
           py::arg("apply_ambiguous"))
      .def("ik", &Kinematics::Ik, py::arg("poses"), py::arg("pr_mode"), py::arg("times_s"))
      .def("compensate", &Kinematics::Compensate, py::arg("poses"), py::arg("pr_mode"), py::arg("times_s"))
      .def("pr_twist", &Kinematics::PrTwist, py::arg("poses"))
      .def("fk", &Kinematics::Fk, py::arg("lengths"), py::arg("with_pr"))
      .def("check", &Kinematics::Check, py::arg("poses"))
      .def("home", &Kinematics::Home)
      .def("calibration", &Kinematics::CalibrationText);
  // The PR modes by their C++ names, upper-cased (PrMode.SIGNED is "signed").
  py::enum_<PrMode> modes(m, "PrMode", "The passive-rotation compensation modes (docs/kinematics.md).");
  std::vector<std::string> names;  // pybind11 copies each name
  for (PrMode mode : kPrModes) {
    std::string name = PrModeName(mode);
    for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    names.push_back(name);
  }
  for (std::size_t k = 0; k < names.size(); ++k) modes.value(names[k].c_str(), kPrModes[k]);
}

}  // namespace edsp::python
