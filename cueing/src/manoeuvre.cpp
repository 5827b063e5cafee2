#include "edsp/cueing/manoeuvre.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "edsp/config_file/config_file.h"
#include "edsp/cueing/raised_cosine.h"

namespace edsp {
namespace {

double PulseAt(const CuePulse& p, double t) {
  const double rise_end = p.start_s + p.rise_s, fall_start = rise_end + p.hold_s;
  if (t < p.start_s || t > fall_start + p.fall_s) return 0.0;
  if (t < rise_end) return p.amplitude * (p.rise_s > 0.0 ? RaisedCosine((t - p.start_s) / p.rise_s) : 1.0);
  if (t <= fall_start) return p.amplitude;
  return p.amplitude * (p.fall_s > 0.0 ? 1.0 - RaisedCosine((t - fall_start) / p.fall_s) : 0.0);
}

double SineAt(const CueSine& s, double t) {
  const double local = t - s.start_s;
  if (local < 0.0 || local > s.duration_s) return 0.0;
  double envelope = 1.0;
  if (s.fade_s > 0.0) envelope = RaisedCosine(local / s.fade_s) * RaisedCosine((s.duration_s - local) / s.fade_s);
  return envelope * s.amplitude * std::sin(2.0 * kPi * s.frequency_hz * local + s.phase_rad);
}

int ReadChannel(const ConfigSection& s) {
  const std::string name = s.String("channel", "");
  const int channel = CueChannelIndex(name.c_str());
  if (channel < 0)
    s.Fail("channel", fmt::format("{} channel = \"{}\": must be one of fx fy fz wx wy wz", s.label(), name));
  return channel;
}

double NonNegative(const ConfigSection& s, const char* key, double fallback) {
  const double value = s.Number(key, fallback);
  if (value < 0.0) s.Fail(key, fmt::format("{} {} = {} must be ≥ 0", s.label(), key, value));
  return value;
}

// A pulse's rise or fall: a step would be a jolt no vehicle makes, and a
// step in specific force is a step in the platform's acceleration.
double Ramp(const ConfigSection& s, const char* key) {
  if (!s.Has(key)) s.Fail("", fmt::format("{} needs {} > 0 (a step is no vehicle's motion)", s.label(), key));
  const double value = s.Number(key, 0.0);
  if (!(value > 0.0))
    s.Fail(key, fmt::format("{} {} = {} must be > 0 (a step is no vehicle's motion)", s.label(), key, value));
  return value;
}

// Beyond what any vehicle a rider survives makes, on one channel.
double ChannelLimit(int channel) { return channel < 3 ? 5.0 * kStandardGravity_m_s2 : kTwoPi; }

// Pulses and sines that add up past a channel's limit, found on the
// manoeuvre sampled at 1 kHz: the channel, the value and when.
void CheckSums(const ConfigSection& root, const Manoeuvre& m) {
  constexpr double kCheckPeriod_s = 1e-3;
  for (double t = 0.0; t <= m.duration_s; t += kCheckPeriod_s) {
    const VehicleSample sample = m.At(t);
    for (int channel = 0; channel < kCueChannels; ++channel) {
      const double value = ChannelValue(sample, channel) - (channel == 2 ? kStandardGravity_m_s2 : 0.0);
      if (std::fabs(value) > ChannelLimit(channel)) {
        root.Fail("", fmt::format("{} adds up to {:.4g} at t = {:.3f} s: beyond {:.4g}", CueChannelName(channel), value,
                                  t, ChannelLimit(channel)));
      }
    }
  }
}

// A name that is safe as a file name (the CSV of a run is named after it).
void CheckName(const ConfigSection& root, const std::string& name) {
  const bool safe = !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!safe) root.Fail("name", fmt::format("name = \"{}\": lower-case letters, digits and _ (at most 64)", name));
}

// A channel's amplitude beyond what any vehicle a rider survives makes:
// a unit mistake (deg/s for rad/s, g for m/s²), refused.
void CheckAmplitude(const ConfigSection& s, int channel, double amplitude) {
  const double limit = ChannelLimit(channel);
  if (std::fabs(amplitude) > limit) {
    s.Fail("amplitude", fmt::format("{} amplitude = {} {} on {}: beyond {} (a unit mistake?)", s.label(), amplitude,
                                    channel < 3 ? "m/s²" : "rad/s", CueChannelName(channel), limit));
  }
}

CuePulse ReadPulse(const ConfigSection& s, double duration_s) {
  s.RejectUnknownKeys({"channel", "start_s", "rise_s", "hold_s", "fall_s", "amplitude"});
  CuePulse p;
  p.channel = ReadChannel(s);
  p.start_s = NonNegative(s, "start_s", 0.0);
  p.rise_s = Ramp(s, "rise_s");
  p.hold_s = NonNegative(s, "hold_s", 0.0);
  p.fall_s = Ramp(s, "fall_s");
  p.amplitude = s.Number("amplitude", 0.0);
  CheckAmplitude(s, p.channel, p.amplitude);
  if (p.start_s + p.rise_s + p.hold_s + p.fall_s > duration_s) {
    s.Fail("start_s", fmt::format("{} ends at {} s, after the manoeuvre's duration_s = {}", s.label(),
                                  p.start_s + p.rise_s + p.hold_s + p.fall_s, duration_s));
  }
  return p;
}

CueSine ReadSine(const ConfigSection& s, double duration_s) {
  s.RejectUnknownKeys({"channel", "start_s", "duration_s", "fade_s", "amplitude", "frequency_hz", "phase_rad"});
  CueSine sine;
  sine.channel = ReadChannel(s);
  sine.start_s = NonNegative(s, "start_s", 0.0);
  sine.duration_s = NonNegative(s, "duration_s", duration_s - sine.start_s);
  sine.fade_s = NonNegative(s, "fade_s", 0.0);
  sine.amplitude = s.Number("amplitude", 0.0);
  sine.frequency_hz = NonNegative(s, "frequency_hz", 0.0);
  sine.phase_rad = s.Number("phase_rad", 0.0);
  CheckAmplitude(s, sine.channel, sine.amplitude);
  if (sine.frequency_hz > 50.0) {
    s.Fail("frequency_hz",
           fmt::format("{} frequency_hz = {}: beyond 50 Hz, no motion base's band", s.label(), sine.frequency_hz));
  }
  if (sine.start_s + sine.duration_s > duration_s + 1e-9) {
    s.Fail("duration_s", fmt::format("{} ends at {} s, after the manoeuvre's duration_s = {}", s.label(),
                                     sine.start_s + sine.duration_s, duration_s));
  }
  if (2.0 * sine.fade_s > sine.duration_s) {
    s.Fail("fade_s", fmt::format("{} fade_s = {} is more than half its duration_s = {}", s.label(), sine.fade_s,
                                 sine.duration_s));
  }
  return sine;
}

}  // namespace

VehicleSample Manoeuvre::At(double t_s) const {
  VehicleSample sample;
  sample.t_s = t_s;
  double value[kCueChannels] = {};
  for (const CuePulse& p : pulses) value[p.channel] += PulseAt(p, t_s);
  for (const CueSine& s : sines) value[s.channel] += SineAt(s, t_s);
  for (int channel = 0; channel < 3; ++channel) {
    sample.specific_force_m_s2(channel) += value[channel];
    sample.angular_velocity_rad_s(channel) = value[channel + 3];
  }
  return sample;
}

Manoeuvre ParseManoeuvre(const std::string& toml_text, const std::string& origin) {
  const ConfigFile file = ConfigFile::Parse(toml_text, origin);
  const ConfigSection root = file.Root();
  root.RejectUnknownKeys({"name", "description", "duration_s", "pulse", "sine"});
  Manoeuvre m;
  m.origin = origin;
  m.name = root.String("name", "");
  if (m.name.empty()) root.Fail("name", "a manoeuvre needs a name = \"...\"");
  CheckName(root, m.name);
  m.description = root.String("description", "");
  m.duration_s = root.Number("duration_s", 0.0);
  if (!(m.duration_s >= 0.1 && m.duration_s <= 3600.0)) {
    root.Fail("duration_s", fmt::format("duration_s = {} must be in [0.1, 3600] s", m.duration_s));
  }
  for (const ConfigSection& s : root.TableArray("pulse")) m.pulses.push_back(ReadPulse(s, m.duration_s));
  for (const ConfigSection& s : root.TableArray("sine")) m.sines.push_back(ReadSine(s, m.duration_s));
  if (m.pulses.empty() && m.sines.empty()) root.Fail("", "a manoeuvre needs at least one [[pulse]] or [[sine]]");
  CheckSums(root, m);
  return m;
}

Manoeuvre LoadManoeuvre(const std::string& path) { return ParseManoeuvre(ConfigFile::ReadText(path), path); }

VehicleSeries SampleManoeuvre(const Manoeuvre& manoeuvre, double period_s) {
  VehicleSeries series;
  series.period_s = period_s;
  const auto n = static_cast<std::size_t>(std::floor(manoeuvre.duration_s / period_s + 1e-9)) + 1;
  series.samples.reserve(n);
  for (std::size_t k = 0; k < n; ++k) series.samples.push_back(manoeuvre.At(static_cast<double>(k) * period_s));
  return series;
}

}  // namespace edsp
