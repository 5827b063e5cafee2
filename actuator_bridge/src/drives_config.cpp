#include "edsp/actuator_bridge/drives_config.h"

#include <cmath>

#include <fmt/format.h>

#include "edsp/actuator_bridge/backend_registry.h"
#include "edsp/kinematics/config_values.h"

namespace edsp {

DrivesConfig ParseDrivesConfig(const std::string& toml_text, const std::string& origin, const DriveParameters& drive) {
  const ConfigSection s = ConfigFile::Parse(toml_text, origin).Section("drives");
  DrivesConfig config;
  if (!s.present()) return config;
  s.RejectUnknownKeys({"backend", "host", "port", "response_timeout_ms", "counts_per_m", "offset_counts", "direction"});
  const std::string backend = s.String("backend", config.backend);
  const BackendKind* kind = FindBackend(backend, &config.backend_note);
  if (kind == nullptr) {
    s.Fail("backend", fmt::format("[drives] backend = \"{}\": known backends are {}", backend, KnownBackends()));
  }
  config.backend = std::string(kind->name);
  config.host = s.String("host", config.host);
  // As a number: an integer cast first would wrap 4294968798 to 1502.
  const double port = s.Number("port", config.port);
  if (!(port >= 1 && port <= 65535) || port != std::floor(port)) {
    s.Fail("port", fmt::format("[drives] port = {} must be an integer in [1, 65535]", port));
  }
  config.port = static_cast<int>(port);
  const double timeout_ms = s.Number("response_timeout_ms", config.response_timeout_s * 1e3);
  if (!(timeout_ms > 0.0 && timeout_ms <= 1000.0)) {
    s.Fail("response_timeout_ms", fmt::format("[drives] response_timeout_ms = {} must be in (0, 1000]", timeout_ms));
  }
  config.response_timeout_s = timeout_ms * 1e-3;
  const bool real = kind->real_drives;
  if (real && !s.Has("counts_per_m")) {
    throw ConfigError(
        fmt::format("{}: [drives] backend = \"{}\" needs counts_per_m (encoder counts per metre "
                    "of leg travel)",
                    origin, config.backend));
  }
  const auto counts_per_m = ReadPerLeg(s, "counts_per_m", {});
  const auto offsets = ReadPerLeg(s, "offset_counts", {});
  const auto directions = ReadPerLeg(s, "direction", {1, 1, 1, 1, 1, 1});
  // Leg travel per motor radian: lead / (2π · gear).
  const double m_per_rad = drive.lead_m / (kTwoPi * drive.gear_ratio);
  for (std::size_t i = 0; i < 6; ++i) {
    if (real && !(counts_per_m[i] > 0.0)) {
      s.Fail("counts_per_m",
             fmt::format("[drives] leg {}: counts_per_m = {} must be positive", i + 1, counts_per_m[i]));
    }
    if (directions[i] != 1.0 && directions[i] != -1.0) {
      s.Fail("direction", fmt::format("[drives] leg {}: direction = {} must be 1 or -1", i + 1, directions[i]));
    }
    if (std::abs(offsets[i]) > 2147483647.0 || offsets[i] != std::floor(offsets[i])) {
      s.Fail("offset_counts",
             fmt::format("[drives] offset_counts of leg {} = {} must be a 32-bit integer", i + 1, offsets[i]));
    }
    cia402::DriveScaling& d = config.scaling[i];
    d.counts_per_rad = counts_per_m[i] * m_per_rad;
    d.direction = static_cast<int>(directions[i]);
    d.offset_counts = static_cast<std::int32_t>(offsets[i]);
  }
  return config;
}

std::optional<std::string> ScalingProblem(const std::array<cia402::DriveScaling, 6>& scaling) {
  for (std::size_t i = 0; i < scaling.size(); ++i) {
    if (const std::optional<std::string> problem = scaling[i].Problem()) {
      return fmt::format("[drives] leg {}: {} (from the config's [drives] counts_per_m and direction)", i + 1,
                         *problem);
    }
  }
  return std::nullopt;
}

DrivesConfig LoadDrivesConfig(const std::string& path, const PlatformConfig& platform) {
  return ParseDrivesConfig(ReadConfigText(path), path, platform.drive);
}

}  // namespace edsp
