// Data recorded with a calibration in force: the export carries the
// correction the kinematics took off each command, the diagnosis reads the
// data against the nominal model (the rig's whole effects) or against the
// calibration (what it leaves), and a second calibration made on data
// recorded with the first holds as well as the first. The truth is the
// rig's (rig/) and the same sessions run without any calibration.
#include <cmath>
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "edsp/diagnosis/recorded_correction.h"
#include "edsp/diagnosis/report.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/forward_kinematics.h"
#include "edsp/sim/offline_run.h"
#include "command_output.h"
#include "offline_session.h"
#include "scratch_dir.h"
#include "platform_models.h"
#include "edsp/node/build_paths.h"

namespace edsp::gap {
namespace {

const std::vector<std::string> kFit = {"Lz", "Lx", "Rz", "Ry", "M1", "M2"};
const std::vector<std::string> kHeldOut = {"Ly", "Rx", "M3"};

RigEffects Rig() { return test_support::OffsetsBacklashAndLead(); }

// `motions` on the rig with `model` applied by the kinematics (empty: none);
// the tracker `noise_m` noisy, drawn by `seed`.
std::string Session(const std::string& name, const std::vector<std::string>& motions, const std::string& model,
                    std::uint64_t seed, double noise_m = 5e-6) {
  OfflineRunOptions o = test_support::OfflineSession(
      motions, 4, 0.3, noise_m, seed, Pose::FromVector((Vector6() << 1.5, -2.0, 0.2, 0.01, -0.01, 0.4).finished()),
      test_support::ScratchDir("recorded_correction_" + name));
  o.calibration_path = model;
  return RunOffline(test_support::kShippedConfig, Rig(), o).csv_path;
}

std::string SaveModel(const Diagnosis& d, const std::string& name) {
  const std::string path = test_support::ScratchDir("recorded_correction_models") + "/" + name + ".json";
  std::ofstream(path) << ModelJson(d).dump(2);
  return path;
}

// The first calibration, diagnosed on a session run without one.
const std::string& First() {
  static const std::string path =
      SaveModel(Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(Session("fit", kFit, "", 1))), "first");
  return path;
}

// The same fit motions run again with the first calibration in force.
const std::string& RecordedWithFirst() {
  static const std::string path = Session("fit_calibrated", kFit, First(), 2);
  return path;
}

// Point A's error as measured in `csv` (held-out motions, a model applied).
double MeasuredRms(const std::string& csv) {
  return Evaluate(test_support::ShippedConfigModel(), LoadMeasurement(csv), EmptyModelJson(), "none").before.rms_m;
}

const EffectResult* Find(const Diagnosis& d, Effect e) {
  for (const EffectResult& r : d.effects) {
    if (r.effect == e) return &r;
  }
  return nullptr;
}

// Against forward kinematics: rows commanded with a correction c land where
// FK puts the shortened legs; read nominally, point A returns to where the
// nominal command puts it (the model's A at the pose) to first order in c:
// within 1.2 µm for a millimetre on every leg, 0.11 µm for 0.3 mm (the
// linearisation's error is quadratic in c); the command and encoders gain
// c, and a row without a correction is left as it was.
TEST(RecordedCorrection, ReadNominallyARowIsWhereTheNominalCommandPutsA) {
  const PlatformModel model = test_support::ShippedConfigModel();
  MeasurementData data;
  data.runs = {"poses"};
  data.has_correction = true;
  for (int k = 0; k < 40; ++k) {
    const double s = 0.1 * k;
    const Pose pose = Pose::FromVector((Vector6() << 0.15 * std::sin(s), 0.12 * std::cos(1.3 * s),
                                        model.home_pose().p_BoMo_B.z() + 0.1 * std::sin(0.7 * s),
                                        0.08 * std::sin(0.9 * s), 0.06 * std::cos(1.1 * s), 0.2 * std::sin(0.5 * s))
                                           .finished());
    MeasurementRow row;
    row.time_s = 0.01 * k;
    row.pose_cmd = pose.ToVector();
    const Vector6 nominal = model.Solve(pose).length_m - model.PrLengthError(pose, PrMode::kSigned);
    const double scale = k % 10 == 3 ? 1.0 : k % 10 == 7 ? 0.3 : 0.0;
    row.leg_corr_m << 1e-3, -0.7e-3, 0.4e-3, -1e-3, 0.2e-3, 0.9e-3;
    row.leg_corr_m *= scale;
    row.leg_cmd_m = nominal - row.leg_corr_m;
    row.has_encoder = k % 20 == 3;
    row.leg_enc_m = row.leg_cmd_m;
    const FkResult landed = SolveForward(model, row.leg_cmd_m, pose);
    ASSERT_TRUE(landed.ok()) << k;
    row.point_m = model.ObservationPoint(landed.pose);
    data.rows.push_back(row);
  }
  double shift_rms = 0.0;
  const MeasurementData read = AsCommandedNominally(model, data, &shift_rms);
  ASSERT_EQ(read.rows.size(), data.rows.size());
  for (std::size_t k = 0; k < data.rows.size(); ++k) {
    const MeasurementRow& was = data.rows[k];
    const MeasurementRow& row = read.rows[k];
    const Vector3 nominal_point = model.ObservationPoint(Pose::FromVector(was.pose_cmd));
    if (was.leg_corr_m.isZero(0.0)) {
      EXPECT_EQ(row.point_m, was.point_m) << k;
      EXPECT_EQ(row.leg_cmd_m, was.leg_cmd_m) << k;
      continue;
    }
    const double scale = was.leg_corr_m(0) / 1e-3;
    EXPECT_GT((was.point_m - nominal_point).norm(), 300e-6 * scale) << k;  // the correction moved A
    EXPECT_LT((row.point_m - nominal_point).norm(), 1.2e-6 * scale * scale) << k;
    EXPECT_LT((row.leg_cmd_m - (was.leg_cmd_m + was.leg_corr_m)).norm(), 1e-15) << k;
    EXPECT_EQ(row.leg_enc_m, was.has_encoder ? Vector6(was.leg_enc_m + was.leg_corr_m) : was.leg_enc_m) << k;
    EXPECT_TRUE(row.leg_corr_m.isZero(0.0)) << k;
  }
  EXPECT_GT(shift_rms, 50e-6);
}

// Noise-free sessions of the same motions with and without the first
// calibration command the same poses (the calibrated run settles first, so
// its samples start a cycle apart: rows are paired by their pose): their
// leg commands differ by exactly the correction the calibrated one recorded.
TEST(RecordedCorrection, TheExportCarriesTheCorrectionTheKinematicsTookOff) {
  const MeasurementData plain = LoadMeasurement(Session("plain_exact", {"M1"}, "", 3, 0.0));
  const MeasurementData calibrated = LoadMeasurement(Session("calibrated_exact", {"M1"}, First(), 3, 0.0));
  for (const MeasurementRow& row : plain.rows) EXPECT_TRUE(row.leg_corr_m.isZero(0.0)) << row.time_s;
  double largest = 0.0, mismatch = 0.0;
  std::size_t paired = 0, j = 0;
  for (const MeasurementRow& row : calibrated.rows) {
    while (j < plain.rows.size() && (plain.rows[j].pose_cmd - row.pose_cmd).norm() > 1e-12 &&
           plain.rows[j].time_s < row.time_s + 0.1) {
      ++j;
    }
    if (j == plain.rows.size() || (plain.rows[j].pose_cmd - row.pose_cmd).norm() > 1e-12) continue;
    const Vector6 difference = plain.rows[j].leg_cmd_m - row.leg_cmd_m;
    mismatch = std::max(mismatch, (difference - row.leg_corr_m).cwiseAbs().maxCoeff());
    largest = std::max(largest, row.leg_corr_m.cwiseAbs().maxCoeff());
    ++paired;
  }
  EXPECT_GT(paired, calibrated.rows.size() * 9 / 10);
  EXPECT_GT(largest, 50e-6);  // the first calibration corrects by tens of µm
  EXPECT_LT(mismatch, 1e-12);
  EXPECT_TRUE(CarriesACorrection(calibrated));
  EXPECT_FALSE(CarriesACorrection(plain));
}

// Against the nominal model a calibrated session shows the rig's whole
// gap, as the same session run without the calibration does; against the
// calibration it shows what the calibration leaves.
TEST(RecordedCorrection, AgainstTheNominalModelACalibratedSessionShowsTheWholeRig) {
  const MeasurementData plain = LoadMeasurement(Session("plain_noisy", {"M1", "Lx"}, "", 4));
  const MeasurementData calibrated = LoadMeasurement(Session("calibrated_noisy", {"M1", "Lx"}, First(), 4));
  const double whole = Diagnose(test_support::ShippedConfigModel(), plain).gap.overall.rms_m;
  const Diagnosis nominal = Diagnose(test_support::ShippedConfigModel(), calibrated);
  DiagnoseOptions against_calibration;
  against_calibration.against = Against::kCalibration;
  const Diagnosis left = Diagnose(test_support::ShippedConfigModel(), calibrated, against_calibration);
  const std::string figures = fmt::format(
      "gap: uncalibrated {:.2f} µm, calibrated against nominal {:.2f} µm, against the calibration {:.2f} µm; the "
      "correction at A {:.2f} µm",
      whole * 1e6, nominal.gap.overall.rms_m * 1e6, left.gap.overall.rms_m * 1e6,
      nominal.recorded_correction_rms_m * 1e6);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  EXPECT_NEAR(nominal.gap.overall.rms_m, whole, 0.03 * whole);
  EXPECT_LT(left.gap.overall.rms_m, 0.5 * whole);
  EXPECT_GT(nominal.recorded_correction_rms_m, 0.5 * whole);
  EXPECT_EQ(nominal.against, Against::kNominal);
  EXPECT_EQ(left.against, Against::kCalibration);
  // The PR compensation the data shows is the PR's alone in both readings.
  EXPECT_EQ(nominal.applied_pr, PrMode::kSigned);
  EXPECT_EQ(left.applied_pr, PrMode::kSigned);
}

// Calibrating twice converges: a second calibration diagnosed on data
// recorded with the first (against the nominal model) names the rig's
// offsets within their σ of the truth and holds out as well as the first.
TEST(RecordedCorrection, ASecondCalibrationOnDataRecordedWithTheFirstHoldsAsWell) {
  const Diagnosis second = Diagnose(test_support::ShippedConfigModel(), LoadMeasurement(RecordedWithFirst()));
  const EffectResult* offsets = Find(second, Effect::kLegOffset);
  ASSERT_NE(offsets, nullptr);
  ASSERT_EQ(offsets->theta.size(), 6);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(offsets->theta(i), Rig().leg_offset.offset_m[static_cast<std::size_t>(i)],
                4.0 * offsets->sigma(i) + 5e-6)
        << "leg " << i + 1;
  }
  const std::string second_model = SaveModel(second, "second");
  const std::string with_first = Session("heldout_first", kHeldOut, First(), 7);
  const double first = MeasuredRms(with_first);
  const double again = MeasuredRms(Session("heldout_second", kHeldOut, second_model, 7));
  const double none = MeasuredRms(Session("heldout_none", kHeldOut, "", 7));
  const std::string figures =
      fmt::format("held out: none {:.2f} µm, first {:.2f} µm, second {:.2f} µm", none * 1e6, first * 1e6, again * 1e6);
  std::printf("%s\n", figures.c_str());
  SCOPED_TRACE(figures);
  EXPECT_LT(first, 0.5 * none);
  EXPECT_LE(again, 1.1 * first);
  // evaluate predicts it from the session recorded with the first: the
  // second model takes the first's place, as in the kinematics.
  const Evaluation predicted = Evaluate(test_support::ShippedConfigModel(), LoadMeasurement(with_first),
                                        nlohmann::json::parse(std::ifstream(second_model)), second_model);
  EXPECT_TRUE(predicted.against_nominal);
  EXPECT_NEAR(predicted.after.rms_m, again, 0.2 * again);
  EXPECT_NEAR(predicted.before.rms_m, none, 0.1 * none);  // the rig's whole gap
}

TEST(RecordedCorrection, TheCommandLineSaysWhatItReadAgainstAndSavesOnlyAWholeCalibration) {
  const std::string data = RecordedWithFirst();
  const auto json = test_support::RunCommand(fmt::format("{} diagnose --config {} --data {} --json",
                                                         BuiltProgram("edsp-gap"), test_support::kShippedConfig, data));
  ASSERT_EQ(json.exit_code, 0) << json.text;
  const nlohmann::json j = nlohmann::json::parse(json.text.substr(json.text.find('{')));
  EXPECT_EQ(j["recorded_correction"]["against"], "nominal");
  EXPECT_GT(j["recorded_correction"]["rms_m"].get<double>(), 10e-6);
  const std::string model = test_support::ScratchDir("recorded_correction_cli") + "/increments.json";
  const auto refused =
      test_support::RunCommand(fmt::format("{} diagnose --config {} --data {} --against calibration --save-model {}",
                                           BuiltProgram("edsp-gap"), test_support::kShippedConfig, data, model));
  EXPECT_EQ(refused.exit_code, 1) << refused.text;
  EXPECT_NE(refused.text.find("--save-model with --against calibration"), std::string::npos) << refused.text;
  EXPECT_NE(refused.text.find(data), std::string::npos) << refused.text;
  EXPECT_FALSE(std::ifstream(model).good());
  const auto text = test_support::RunCommand(fmt::format("{} diagnose --config {} --data {} --against calibration",
                                                         BuiltProgram("edsp-gap"), test_support::kShippedConfig, data));
  ASSERT_EQ(text.exit_code, 0) << text.text;
  EXPECT_NE(text.text.find("diagnosed against it, so the effects are what it leaves"), std::string::npos) << text.text;
  const auto bad = test_support::RunCommand(fmt::format("{} diagnose --config {} --data {} --against factory",
                                                        BuiltProgram("edsp-gap"), test_support::kShippedConfig, data));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.text.find("factory"), std::string::npos) << bad.text;
}

}  // namespace
}  // namespace edsp::gap
