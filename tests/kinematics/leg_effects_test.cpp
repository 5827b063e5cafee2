// The vocabulary table (kinematics/src/leg_effects.cpp): every parameter of every
// effect read once, by a named group; sizes, limits and priors in the order
// that keeps a real rig's calibration both fittable and accepted.
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "edsp/kinematics/leg_effects.h"

namespace edsp::calibration {
namespace {

// How many groups read θ[k]: a polar pair's amplitude and phase count once.
int Readers(Effect e, int k) {
  int readers = 0;
  for (const ParameterGroup& g : ParameterGroups(e)) {
    if (g.layout == ParameterLayout::kPerLegPhase) continue;
    const bool pair = g.layout == ParameterLayout::kPerLegAmplitude;
    for (int v = 0; v < ValueCount(g); ++v) {
      const int at = ThetaIndex(g, v);
      if (at == k || (pair && at + 1 == k)) ++readers;
    }
  }
  return readers;
}

TEST(LegEffects, EveryParameterOfEveryEffectIsReadByExactlyOneGroup) {
  for (Effect e : AllEffects()) {
    for (int k = 0; k < ParameterCount(e); ++k) EXPECT_EQ(Readers(e, k), 1) << EffectName(e) << " θ[" << k << "]";
    EXPECT_EQ(Readers(e, ParameterCount(e)), 0) << EffectName(e) << ": a group reads past its θ";
  }
}

// A periodic error's amplitude and phase read the same (sin, cos − 1) pairs.
TEST(LegEffects, ThePhaseOfAPairReadsTheSameThetaAsItsAmplitude) {
  const std::vector<ParameterGroup> periodic = ParameterGroups(Effect::kPeriodicLeadError);
  ASSERT_EQ(periodic.size(), 2u);
  ASSERT_EQ(ValueCount(periodic[0]), ValueCount(periodic[1]));
  for (int k = 0; k < ValueCount(periodic[0]); ++k) {
    EXPECT_EQ(ThetaIndex(periodic[0], k), ThetaIndex(periodic[1], k)) << "leg " << k + 1;
  }
}

TEST(LegEffects, NamesParseBackAndKeysAreUniquePerEffect) {
  for (Effect e : AllEffects()) {
    Effect parsed = Effect::kThermalDrift;
    ASSERT_TRUE(ParseEffect(EffectName(e), &parsed)) << EffectName(e);
    EXPECT_EQ(parsed, e);
    std::set<std::string> keys;
    for (const ParameterGroup& g : ParameterGroups(e)) EXPECT_TRUE(keys.insert(g.key).second) << g.key;
    EXPECT_FALSE(keys.empty()) << EffectName(e);
  }
  Effect parsed = Effect::kLegOffset;
  EXPECT_FALSE(ParseEffect("leg_offsets", &parsed));
}

// A prior narrower than a real rig's value would bias the fit toward zero; a
// limit below it would refuse a true calibration.
TEST(LegEffects, TypicalSizesLieBelowTheLimitAndThePriorOfTheirEffect) {
  for (Effect e : AllEffects()) {
    for (int k = 0; k < ParameterCount(e); ++k) {
      const double typical = TypicalParameterSize(e, k);
      EXPECT_GT(typical, 0.0) << EffectName(e) << " θ[" << k << "]";
      EXPECT_LT(typical, ParameterLimit(e)) << EffectName(e) << " θ[" << k << "]";
      EXPECT_LE(typical, PriorSigma(e)) << EffectName(e) << " θ[" << k << "]";
    }
  }
}

TEST(LegEffects, GroupsReadTheirValuesFromTheBasisLayout) {
  double theta[36];
  for (int k = 0; k < 36; ++k) theta[k] = 0.5 + k;
  const std::vector<ParameterGroup> joints = ParameterGroups(Effect::kJointPosition);
  ASSERT_EQ(joints.size(), 2u);
  EXPECT_EQ(GroupValue(joints[1], theta, 3 * 4 + 2), theta[18 + 3 * 4 + 2]);  // platform z of leg 5
  const std::vector<ParameterGroup> pr = ParameterGroups(Effect::kPassiveRotation);
  EXPECT_EQ(GroupValue(pr[1], theta, 0), 1.0 + theta[1]);  // a scale read as 1 + θ
  const std::vector<ParameterGroup> periodic = ParameterGroups(Effect::kPeriodicLeadError);
  // Leg 3's pair (sin, cos − 1) = (4.5, 5.5): s·sin φ + c·(cos φ − 1) = A·sin(φ + ψ) + const.
  EXPECT_DOUBLE_EQ(GroupValue(periodic[0], theta, 2), std::hypot(4.5, 5.5));
  EXPECT_DOUBLE_EQ(GroupValue(periodic[1], theta, 2), std::atan2(5.5, 4.5));
  EXPECT_FALSE(HasSigma(periodic[0]));
}

}  // namespace
}  // namespace edsp::calibration
