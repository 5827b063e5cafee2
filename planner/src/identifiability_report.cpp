#include "edsp/planner/identifiability_report.h"

#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "edsp/planner/motion_library.h"
#include "edsp/planner/planner.h"

namespace edsp {
namespace {

nlohmann::json ToJson(const Identifiability& row) {
  return {{"effects", row.effects}, {"parameters", row.parameters},
          {"samples", row.samples}, {"condition", row.condition},
          {"o1", row.o1},           {"o3", row.o3}};
}

void PrintJson(const TrajectorySequence& motions, const TrajectorySequence& reference,
               const std::vector<Identifiability>& ours, const std::vector<Identifiability>& theirs,
               const IdentifiabilityOptions& options) {
  nlohmann::json out = {{"rate_hz", options.rate_hz}, {"noise_sigma_m", options.noise_sigma_m}};
  out["motions"] = {{"duration_s", motions.duration_s()}, {"effects", nlohmann::json::array()}};
  out["paper"] = {{"duration_s", reference.duration_s()}, {"effects", nlohmann::json::array()}};
  for (const Identifiability& row : ours) out["motions"]["effects"].push_back(ToJson(row));
  for (const Identifiability& row : theirs) out["paper"]["effects"].push_back(ToJson(row));
  std::cout << out.dump(2) << "\n";
}

void PrintTable(const TrajectorySequence& motions, const TrajectorySequence& reference,
                const std::vector<Identifiability>& ours, const std::vector<Identifiability>& theirs,
                const IdentifiabilityOptions& options) {
  std::printf("identifiability at %.0f Hz, tracker noise %.1f um per axis; parameters in typical sizes\n",
              options.rate_hz, options.noise_sigma_m * 1e6);
  std::printf("these motions %.1f s, the paper's four (Lz Lx Rz Ry) %.1f s\n\n", motions.duration_s(),
              reference.duration_s());
  std::printf("%-20s %4s | %10s %9s %9s | %10s %9s %9s\n", "effects", "par", "condition", "O1", "O3", "paper cond",
              "O1", "O3");
  for (std::size_t k = 0; k < ours.size(); ++k) {
    const Identifiability& a = ours[k];
    const Identifiability& b = theirs[k];
    std::printf("%-20s %4d | %10.3g %9.3g %9.3g | %10.3g %9.3g %9.3g\n", a.effects.c_str(), a.parameters, a.condition,
                a.o1, a.o3, b.condition, b.o1, b.o3);
  }
}

}  // namespace

void ReportIdentifiability(const PlatformModel& model, const TrajectorySequence& motions,
                           const PaperMotionOptions& paper, const IdentifiabilityOptions& options, bool json) {
  CheckTrajectory(model, motions);
  const auto reference = MotionSequence(model, PaperMotionNames(), paper);
  const std::vector<Identifiability> ours = AssessIdentifiability(model, motions, options);
  const std::vector<Identifiability> theirs = AssessIdentifiability(model, *reference, options);
  (json ? PrintJson : PrintTable)(motions, *reference, ours, theirs, options);
}

}  // namespace edsp
