#include <algorithm>
#include <numeric>

#include "edsp/diagnosis/design.h"

namespace edsp::gap {

Design WithoutColumns(const Design& d) {
  Design out;
  out.residual = d.residual;
  out.frame = d.frame;
  out.effect = d.effect;
  out.sample_run = d.sample_run;
  out.run_samples = d.run_samples;
  out.runs = d.runs;
  out.source_row = d.source_row;
  out.point_per_leg = d.point_per_leg;
  out.model_point = d.model_point;
  out.leg_velocity_m_s = d.leg_velocity_m_s;
  out.leg_accel_m_s2 = d.leg_accel_m_s2;
  out.point_accel_m_s2 = d.point_accel_m_s2;
  out.load_moment_per_kg = d.load_moment_per_kg;
  out.servo_error_m = d.servo_error_m;
  out.time_s = d.time_s;
  out.displacement = d.displacement;
  out.has_encoder = d.has_encoder;
  out.applied_pr_ratio = d.applied_pr_ratio;
  out.applied_pr = d.applied_pr;
  out.R0 = d.R0;
  out.t0 = d.t0;
  return out;
}

Design KeepOnly(const Design& d, const std::vector<Effect>& keep) {
  Design out = WithoutColumns(d);
  out.frame = d.frame;
  out.nuisance = d.nuisance;
  const int first = d.frame.begin + d.frame.count + d.nuisance.count;
  std::vector<Eigen::Index> columns(static_cast<std::size_t>(first));
  std::iota(columns.begin(), columns.end(), Eigen::Index{0});
  for (Effect e : AllEffects()) {
    ColumnRange& r = out.effect[static_cast<std::size_t>(e)];
    const bool kept = std::find(keep.begin(), keep.end(), e) != keep.end();
    const ColumnRange was = d.Of(e);
    r = {static_cast<int>(columns.size()), kept ? was.count : 0};
    for (int k = 0; kept && k < was.count; ++k) columns.push_back(was.begin + k);
  }
  out.columns = d.columns(Eigen::all, columns);
  return out;
}

}  // namespace edsp::gap
