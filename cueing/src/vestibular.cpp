#include "edsp/cueing/vestibular.h"

#include <stdexcept>

#include <fmt/format.h>

namespace edsp {
namespace {

DiscreteFilter ChannelFilter(const VestibularParameters& parameters, int channel, double period_s) {
  return DiscreteFilter(
      channel < 3 ? OtolithTransferFunction(parameters.otolith) : CanalTransferFunction(parameters.canal), period_s);
}

}  // namespace

double VestibularParameters::Threshold(int channel) const {
  if (channel < 0 || channel >= kCueChannels) throw std::out_of_range(fmt::format("no cue channel {}", channel));
  return channel < 3 ? otolith.threshold_m_s2(channel) : canal.threshold_rad_s(channel - 3);
}

TransferFunction OtolithTransferFunction(const OtolithParameters& p) {
  return {{p.tau_a_s, 1.0}, {p.tau_l_s * p.tau_s_s, p.tau_l_s + p.tau_s_s, 1.0}};
}

TransferFunction CanalTransferFunction(const CanalParameters& p) {
  const TransferFunction adaptation{{p.tau_a_s, 0.0}, {p.tau_a_s, 1.0}};
  const TransferFunction cupula{{p.tau_l_s, 0.0}, {p.tau_l_s * p.tau_s_s, p.tau_l_s + p.tau_s_s, 1.0}};
  return Series(cupula, adaptation);
}

Vestibular::Vestibular(const VestibularParameters& parameters, double period_s)
    : filters_{ChannelFilter(parameters, 0, period_s), ChannelFilter(parameters, 1, period_s),
               ChannelFilter(parameters, 2, period_s), ChannelFilter(parameters, 3, period_s),
               ChannelFilter(parameters, 4, period_s), ChannelFilter(parameters, 5, period_s)} {
  filters_[2].Reset(kStandardGravity_m_s2);
}

std::array<double, kCueChannels> Vestibular::Perceive(const VehicleSample& sample) {
  std::array<double, kCueChannels> perceived{};
  for (int channel = 0; channel < kCueChannels; ++channel) {
    perceived[static_cast<std::size_t>(channel)] =
        filters_[static_cast<std::size_t>(channel)].Step(ChannelValue(sample, channel));
  }
  return perceived;
}

std::array<std::vector<double>, kCueChannels> Perceive(const VestibularParameters& parameters,
                                                       const VehicleSeries& series) {
  Vestibular vestibular(parameters, series.period_s);
  std::array<std::vector<double>, kCueChannels> perceived;
  for (auto& channel : perceived) channel.reserve(series.samples.size());
  for (const VehicleSample& sample : series.samples) {
    const auto now = vestibular.Perceive(sample);
    for (int channel = 0; channel < kCueChannels; ++channel) {
      perceived[static_cast<std::size_t>(channel)].push_back(now[static_cast<std::size_t>(channel)]);
    }
  }
  return perceived;
}

}  // namespace edsp
