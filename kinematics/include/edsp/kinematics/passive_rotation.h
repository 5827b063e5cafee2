#pragma once
// The lead screws' passive rotation (PR), architecture.md "The passive-rotation
// model". For leg i: jb = u × ja, je = u × jd (jd = R·jd0), and the twist of
// the upper leg body relative to the lower one is the SIGNED angle
//   theta = atan2((jb × je)·u, jb·je).
// The PR length error (actual length minus encoder-implied length) is
//   s · wrap(theta − theta_home) / 2π · lead.

#include <cstdint>

#include "edsp/kinematics/types.h"

namespace edsp {

// How a compensation (or an analysis) models PR. Values 0..2 are the wire
// values of interfaces.md §1; 3 is an edsp extension for LinuxCNC users.
enum class PrMode : std::int8_t {
  kNone = 0,      // no PR model
  kUnsigned = 1,  // the paper's Eq. (9): arccos(jb·je), loses the sign
  kSigned = 2,    // atan2 twist relative to home (correct)
  kAsin = 3,      // LinuxCNC genhexkins: asin(sin theta), folds past ±90°
};

// Every mode, in wire order (leg_command_t.PR_*): what lists them (Python's enum) reads this.
inline constexpr PrMode kPrModes[] = {PrMode::kNone, PrMode::kUnsigned, PrMode::kSigned, PrMode::kAsin};

const char* PrModeName(PrMode mode);               // "none", "unsigned", "signed", "asin"
bool ParsePrMode(const char* text, PrMode* mode);  // accepts names and 0..3

// Signed twist of each leg for unit leg axes u_B and joint axes ja_B, jd_B
// (jd already rotated into {B}). Lengths of jb, je cancel inside atan2.
Vector6 SignedTwist(const Matrix36& u_B, const Matrix36& ja_B, const Matrix36& jd_B);

// The angle a PR mode tracks, from the signed twist: theta, |theta| (equal to
// arccos(jb·je)), asin(sin theta); zero for kNone.
double TwistAsModelled(double signed_twist_rad, PrMode mode);

// Wraps an angle difference into (−π, π].
double WrapAngle(double angle_rad);

}  // namespace edsp
