#pragma once
// A saved model (`edsp-gap-model/1`, report.h's ModelJson) read as edsp-gap
// applies it to new data: the bases' settings it was fitted with and every
// effect not marked `"apply": false` (`evaluate`'s rule: an older file's
// ambiguous entries too), each with its parameters and, where the file has
// them, their 1-σ. `drift` and `compare`'s prediction pass it
// AppliedModelJson's output: what the kinematics applies.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

struct SavedEffect {
  Effect effect = Effect::kLegOffset;
  Verdict verdict = Verdict::kIdentified;  // the file's (none: identified)
  Eigen::VectorXd theta;
  Eigen::VectorXd sigma;  // zeros when the file has none (saved before they were)
};

// Throws MeasurementError naming `origin` and the key that is wrong.
DesignOptions SavedDesignOptions(const nlohmann::json& saved, const std::string& origin);
// The tracker frame's rotation the fit found (`tracker_rotation`, 9 numbers
// row by row), if the model has one. Throws MeasurementError naming the key
// when it is not a rotation.
std::optional<Matrix3> SavedTrackerRotation(const nlohmann::json& saved, const std::string& origin);
// The rotation as the model writes it, row by row.
nlohmann::json TrackerRotationJson(const Matrix3& R);
std::vector<SavedEffect> SavedAppliedEffects(const nlohmann::json& saved, const DesignOptions& options,
                                             const std::string& origin);

}  // namespace edsp::gap
