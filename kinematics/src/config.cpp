#include "edsp/kinematics/config.h"

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

namespace edsp {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Reads one section of the file, naming the file, line and key in every error.
class SectionReader {
 public:
  SectionReader(const toml::table& root, const char* name, const std::string& origin)
      : name_(name), origin_(origin) {
    const toml::node* node = root.get(name);
    if (node != nullptr) {
      table_ = node->as_table();
      if (table_ == nullptr) Fail(*node, fmt::format("[{}] must be a table", name));
    }
  }

  bool present() const { return table_ != nullptr; }
  bool Has(const char* key) const { return table_ != nullptr && table_->get(key) != nullptr; }

  // Every key of the section must be one we know: a typo such as `lead = 0.01`
  // must not silently fall back to a default on a rig.
  void RejectUnknownKeys(std::initializer_list<const char*> known) const {
    if (table_ == nullptr) return;
    for (auto&& [key, node] : *table_) {
      bool found = false;
      std::string list;
      for (const char* k : known) {
        found = found || key.str() == k;
        list += list.empty() ? k : fmt::format(", {}", k);
      }
      if (!found) {
        Fail(node, fmt::format("unknown key [{}] {} (known keys: {})", name_, key.str(), list));
      }
    }
  }

  std::string String(const char* key, const std::string& fallback) const {
    const toml::node* node = Get(key);
    if (node == nullptr) return fallback;
    if (!node->is_string()) Fail(*node, fmt::format("[{}] {} must be a string", name_, key));
    return *node->value<std::string>();
  }

  double Number(const char* key, double fallback) const {
    const toml::node* node = Get(key);
    return node == nullptr ? fallback : ToNumber(*node, key);
  }

  int Integer(const char* key, int fallback) const {
    const toml::node* node = Get(key);
    if (node == nullptr) return fallback;
    if (!node->is_integer()) Fail(*node, fmt::format("[{}] {} must be an integer", name_, key));
    return static_cast<int>(*node->value<std::int64_t>());
  }

  Vector3 Vector(const char* key, const Vector3& fallback) const {
    const toml::node* node = Get(key);
    return node == nullptr ? fallback : ToVector3(*node, key, "");
  }

  // A 6x3 array of arrays, returned as one column per leg.
  bool Rows6(const char* key, Matrix36* out) const {
    const toml::node* node = Get(key);
    if (node == nullptr) return false;
    const toml::array* rows = node->as_array();
    if (rows == nullptr || rows->size() != kNumLegs) {
      Fail(*node, fmt::format("[{}] {} must be an array of 6 rows [x, y, z]", name_, key));
    }
    for (int i = 0; i < kNumLegs; ++i) {
      out->col(i) = ToVector3((*rows)[static_cast<std::size_t>(i)], key,
                              fmt::format(" row {}", i + 1));
    }
    return true;
  }

  [[noreturn]] void Fail(const toml::node& node, const std::string& what) const {
    throw ConfigError(fmt::format("{}:{}: {}", origin_, node.source().begin.line, what));
  }

 private:
  const toml::node* Get(const char* key) const {
    return table_ == nullptr ? nullptr : table_->get(key);
  }

  double ToNumber(const toml::node& node, const std::string& key) const {
    if (!node.is_number()) Fail(node, fmt::format("[{}] {} must be a number", name_, key));
    const double value = *node.value<double>();
    if (!std::isfinite(value)) {
      Fail(node, fmt::format("[{}] {} = {} must be finite", name_, key, value));
    }
    return value;
  }

  Vector3 ToVector3(const toml::node& node, const std::string& key, const std::string& row) const {
    const toml::array* xyz = node.as_array();
    if (xyz == nullptr || xyz->size() != 3) {
      Fail(node, fmt::format("[{}] {}{} must be [x, y, z]", name_, key, row));
    }
    Vector3 v;
    for (int k = 0; k < 3; ++k) v(k) = ToNumber((*xyz)[static_cast<std::size_t>(k)], key + row);
    return v;
  }

  const toml::table* table_ = nullptr;
  const char* name_;
  const std::string& origin_;
};

void ReadGeometry(const SectionReader& s, const std::string& origin, PlatformConfig* config) {
  s.RejectUnknownKeys({"preset", "home_height_m", "base_joints_m", "platform_joints_m",
                       "base_axes", "platform_axes"});
  config->preset = s.String("preset", "");
  if (!config->preset.empty() && config->preset != "huang2021") {
    throw ConfigError(fmt::format("{}: [geometry] preset = \"{}\" is unknown (known: huang2021)",
                                  origin, config->preset));
  }
  PlatformGeometry& g = config->geometry;
  Huang2021Dimensions dims;
  dims.home_height_m = s.Number("home_height_m", dims.home_height_m);
  if (!config->preset.empty()) g = Huang2021Geometry(dims);
  // Explicit arrays override the preset, one by one; without a preset all four
  // and the home height are required.
  const char* keys[] = {"base_joints_m", "platform_joints_m", "base_axes", "platform_axes"};
  Matrix36* targets[] = {&g.p_BoBi_B, &g.p_MoPi_M, &g.ja_B, &g.jd_M};
  for (int k = 0; k < 4; ++k) {
    if (!s.Rows6(keys[k], targets[k]) && config->preset.empty()) {
      throw ConfigError(fmt::format(
          "{}: missing key [geometry] {} (give it, or set preset = \"huang2021\")", origin,
          keys[k]));
    }
  }
  if (config->preset.empty() && !s.Has("home_height_m")) {
    throw ConfigError(fmt::format("{}: missing key [geometry] home_height_m", origin));
  }
  g.home_height_m = dims.home_height_m;
}

void ReadDrive(const SectionReader& s, DriveParameters* drive) {
  s.RejectUnknownKeys({"lead_m", "pr_sign", "gear_ratio"});
  drive->lead_m = s.Number("lead_m", drive->lead_m);
  drive->pr_sign = s.Integer("pr_sign", drive->pr_sign);
  drive->gear_ratio = s.Number("gear_ratio", drive->gear_ratio);
}

void ReadLimits(const SectionReader& s, WorkspaceLimits* limits) {
  s.RejectUnknownKeys({"leg_min_m", "leg_max_m", "joint_angle_max_rad", "jacobian_condition_max",
                       "leg_speed_max_m_s"});
  limits->leg_speed_max_m_s = s.Number("leg_speed_max_m_s", limits->leg_speed_max_m_s);
  limits->leg_min_m = s.Number("leg_min_m", limits->leg_min_m);
  limits->leg_max_m = s.Number("leg_max_m", limits->leg_max_m);
  limits->joint_angle_max_rad = s.Number("joint_angle_max_rad", limits->joint_angle_max_rad);
  limits->jacobian_condition_max =
      s.Number("jacobian_condition_max", limits->jacobian_condition_max);
}

void Require(bool ok, const std::string& origin, const std::string& what) {
  if (!ok) throw ConfigError(fmt::format("{}: {}", origin, what));
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(fmt::format("{}: cannot open config file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

PlatformConfig Huang2021Config() {
  PlatformConfig config;
  config.preset = "huang2021";
  config.geometry = Huang2021Geometry();
  config.p_MoA_M = Vector3(Huang2021Dimensions{}.platform_radius_m, 0.0, 0.0);
  return config;
}

void ValidateConfig(const PlatformConfig& c, const std::string& origin) {
  ValidateGeometry(c.geometry, origin);
  const DriveParameters& d = c.drive;
  // A lead above 0.5 m per turn is no lead screw; a typo in units (mm for m).
  Require(d.lead_m > 0.0 && d.lead_m <= 0.5, origin,
          fmt::format("[drive] lead_m = {} must be in (0, 0.5] m per screw turn", d.lead_m));
  Require(d.pr_sign == 1 || d.pr_sign == -1, origin,
          fmt::format("[drive] pr_sign = {} must be 1 or -1", d.pr_sign));
  Require(d.gear_ratio > 0.0 && d.gear_ratio <= 1000.0, origin,
          fmt::format("[drive] gear_ratio = {} must be in (0, 1000] motor turns per screw turn",
                      d.gear_ratio));
  Require(c.p_MoA_M.allFinite() && c.p_MoA_M.norm() <= 100.0, origin,
          "[observation] point_m must be finite and within 100 m of the platform centre");
  const WorkspaceLimits& l = c.limits;
  Require(l.leg_min_m > 0.0 && l.leg_min_m < l.leg_max_m, origin,
          fmt::format("[limits] leg_min_m = {} must be positive and below leg_max_m = {}",
                      l.leg_min_m, l.leg_max_m));
  Require(l.joint_angle_max_rad > 0.0 && l.joint_angle_max_rad < kPi / 2, origin,
          fmt::format("[limits] joint_angle_max_rad = {} must be in (0, pi/2)",
                      l.joint_angle_max_rad));
  // Above 10 m/s no lead-screw leg moves; a unit typo (mm/s for m/s).
  Require(l.leg_speed_max_m_s > 0.0 && l.leg_speed_max_m_s <= 10.0, origin,
          fmt::format("[limits] leg_speed_max_m_s = {} must be in (0, 10] m/s", l.leg_speed_max_m_s));
  Require(l.jacobian_condition_max >= 1.0, origin,
          fmt::format("[limits] jacobian_condition_max = {} must be at least 1",
                      l.jacobian_condition_max));
}

PlatformConfig ParseConfig(const std::string& toml_text, const std::string& origin) {
  toml::table root;
  try {
    root = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format("{}:{}:{}: {}", origin, e.source().begin.line,
                                  e.source().begin.column, e.description()));
  }
  PlatformConfig config;
  const SectionReader geometry(root, "geometry", origin);
  Require(geometry.present(), origin, "missing section [geometry]");
  ReadGeometry(geometry, origin, &config);
  ReadDrive(SectionReader(root, "drive", origin), &config.drive);
  ReadLimits(SectionReader(root, "limits", origin), &config.limits);
  const SectionReader observation(root, "observation", origin);
  observation.RejectUnknownKeys({"point_m"});
  const bool preset_point = !config.preset.empty();
  Require(preset_point || observation.Has("point_m"), origin,
          "missing key [observation] point_m (no preset gives a default)");
  config.p_MoA_M = observation.Vector(
      "point_m", Vector3(Huang2021Dimensions{}.platform_radius_m, 0.0, 0.0));
  ValidateConfig(config, origin);
  return config;
}

PlatformConfig LoadConfigFile(const std::string& path) { return ParseConfig(ReadFile(path), path); }

}  // namespace edsp
