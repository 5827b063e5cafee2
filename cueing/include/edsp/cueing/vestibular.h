#pragma once
// What a rider perceives of a motion: the vestibular models of Telban &
// Cardullo (NASA CR-2005-213747), the ones model-based cueing minimises
// and scores against (docs/cueing.md, "Perception"). Per axis:
//   otoliths, specific force:    K (τa s + 1) / ((τL s + 1)(τS s + 1))
//   semicircular canals, angular velocity, with adaptation:
//                                τL τa s² / ((τL s + 1)(τS s + 1)(τa s + 1))
// K is taken as 1 (steady specific force perceived as itself, in m/s²; the
// paper's K scales afferent firing, which a comparison of two motions
// through the same model does not need), so that the thresholds, in the
// input's units, can be laid beside the perceived error.

#include <array>

#include "edsp/cueing/linear_filter.h"
#include "edsp/cueing/vehicle_motion.h"

namespace edsp {

struct OtolithParameters {
  double tau_a_s = 13.2;
  double tau_l_s = 5.33;
  double tau_s_s = 0.66;
  Vector3 threshold_m_s2 = Vector3(0.17, 0.17, 0.28);
};

struct CanalParameters {
  double tau_l_s = 5.73;
  double tau_s_s = 0.005;
  double tau_a_s = 80.0;
  Vector3 threshold_rad_s = Vector3(3.0, 3.6, 2.6) * (kPi / 180.0);
};

struct VestibularParameters {
  OtolithParameters otolith;
  CanalParameters canal;
  // The threshold of channel `channel` (CueChannelName's order).
  double Threshold(int channel) const;
};

TransferFunction OtolithTransferFunction(const OtolithParameters& parameters);
TransferFunction CanalTransferFunction(const CanalParameters& parameters);

// The six channels' models, run sample by sample. Starts perceiving a
// rider at rest (gravity felt forever), as every run does.
class Vestibular {
 public:
  Vestibular(const VestibularParameters& parameters, double period_s);
  // Perceived fx fy fz (m/s²) wx wy wz (rad/s) for this sample.
  std::array<double, kCueChannels> Perceive(const VehicleSample& sample);

 private:
  std::array<DiscreteFilter, kCueChannels> filters_;
};

// The perceived channels of a whole series: [channel][sample].
std::array<std::vector<double>, kCueChannels> Perceive(const VestibularParameters& parameters,
                                                       const VehicleSeries& series);

}  // namespace edsp
