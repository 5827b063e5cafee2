#include "edsp/blindrig/blind_setup.h"

namespace edsp::blind {

BlindRigSetup SetupFromConfig(const PlatformConfig& config) {
  BlindRigSetup setup;
  const PlatformGeometry& g = config.geometry;
  setup.geometry.base_joint = g.p_BoBi_B;
  setup.geometry.platform_joint = g.p_MoPi_M;
  setup.geometry.base_axis = g.ja_B;
  setup.geometry.platform_axis = g.jd_M;
  setup.geometry.home_height_m = g.home_height_m;
  setup.geometry.point_M = config.p_MoA_M;
  setup.lead_m = config.drive.lead_m;
  setup.pr_sign = config.drive.pr_sign;
  return setup;
}

}  // namespace edsp::blind
