#include "edsp/cueing/manoeuvre_variants.h"

#include <random>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace edsp {
namespace {

void CheckRange(double min, double max, const char* what) {
  if (!(min > 0.0 && min <= max && max <= 2.0)) {
    throw std::invalid_argument(
        fmt::format("manoeuvre variation: {} from {} to {} (within (0, 2], min ≤ max)", what, min, max));
  }
}

// FNV-1a: the same on every build, unlike std::hash.
std::uint64_t NameHash(const std::string& name) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : name) h = (h ^ c) * 1099511628211ULL;
  return h;
}

}  // namespace

std::vector<Manoeuvre> ManoeuvreVariants(const Manoeuvre& manoeuvre, int count, std::uint64_t seed,
                                         const ManoeuvreVariation& variation) {
  CheckRange(variation.amplitude_min, variation.amplitude_max, "amplitude");
  CheckRange(variation.hold_min, variation.hold_max, "hold");
  // One stream per manoeuvre: adding a file does not redraw the others.
  const std::uint64_t name = NameHash(manoeuvre.name);
  std::seed_seq seeds{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(name), static_cast<std::uint32_t>(name >> 32)};
  std::mt19937_64 random(seeds);
  std::uniform_real_distribution<double> amplitude(variation.amplitude_min, variation.amplitude_max);
  std::uniform_real_distribution<double> hold(variation.hold_min, variation.hold_max);
  std::vector<Manoeuvre> variants;
  for (int k = 0; k < count; ++k) {
    Manoeuvre v = manoeuvre;
    const double a = amplitude(random), h = hold(random);
    v.name = fmt::format("{}_v{}", manoeuvre.name, k);
    v.description = fmt::format("{}, amplitudes ×{:.2f}, holds ×{:.2f}", manoeuvre.description, a, h);
    for (CuePulse& p : v.pulses) {
      p.amplitude *= a;
      p.hold_s *= h;
    }
    for (CueSine& s : v.sines) s.amplitude *= a;
    variants.push_back(std::move(v));
  }
  return variants;
}

}  // namespace edsp
