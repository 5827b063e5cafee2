#pragma once
// Fractions as people read them in notes and tables: one decimal, and
// never "-0.0%" for a cut that rounds to nothing.

#include <string>

namespace edsp::gap {

// A fraction as a percentage with one decimal: "0.0%" for one that rounds
// to zero, never "-0.0%" (an effect that gains nothing held out).
std::string Percent(double fraction);

// A held-out cut: "2.1% better", "0.4% worse", "no better".
std::string HeldOutChange(double cv_gain);

}  // namespace edsp::gap
