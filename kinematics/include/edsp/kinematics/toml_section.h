#pragma once
// Reading one TOML section of a config file with errors that name the file,
// line and key ("huang2021.toml:12: [drive] lead_m = 10 must be in (0, 0.5]").
// Shared by the platform config and the rig's effects.

#include <array>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "edsp/kinematics/config.h"

namespace edsp {

// The whole file parsed; a syntax error becomes a ConfigError naming the
// file, line and column.
inline toml::table ParseTomlText(const std::string& text, const std::string& origin) {
  try {
    return toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    throw ConfigError(
        fmt::format("{}:{}:{}: {}", origin, e.source().begin.line, e.source().begin.column, e.description()));
  }
}

// Reads one section of the file, naming the file, line and key in every error.
class SectionReader {
 public:
  SectionReader(const toml::table& root, const char* name, const std::string& origin)
      : SectionReader(root.get(name), name, origin) {}
  // A nested table, e.g. root["rig"]["effects"]["backlash"] named "rig.effects.backlash".
  SectionReader(const toml::node* node, std::string name, const std::string& origin)
      : name_(std::move(name)), origin_(origin) {
    if (node != nullptr) {
      table_ = node->as_table();
      if (table_ == nullptr) Fail(*node, fmt::format("[{}] must be a table", name_));
    }
  }
  const toml::table* table() const { return table_; }
  const std::string& name() const { return name_; }

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

  bool Bool(const char* key, bool fallback) const {
    const toml::node* node = Get(key);
    if (node == nullptr) return fallback;
    if (!node->is_boolean()) Fail(*node, fmt::format("[{}] {} must be true or false", name_, key));
    return *node->value<bool>();
  }

  // One number for every leg, or an array of 6.
  std::array<double, 6> PerLeg(const char* key, const std::array<double, 6>& fallback) const {
    const toml::node* node = Get(key);
    if (node == nullptr) return fallback;
    std::array<double, 6> out{};
    if (node->is_number()) {
      out.fill(ToNumber(*node, key));
      return out;
    }
    const toml::array* values = node->as_array();
    if (values == nullptr || values->size() != 6) {
      Fail(*node, fmt::format("[{}] {} must be a number or an array of 6 (one per leg)", name_, key));
    }
    for (std::size_t i = 0; i < 6; ++i) out[i] = ToNumber((*values)[i], fmt::format("{}[{}]", key, i + 1));
    return out;
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
      out->col(i) = ToVector3((*rows)[static_cast<std::size_t>(i)], key, fmt::format(" row {}", i + 1));
    }
    return true;
  }

  [[noreturn]] void Fail(const toml::node& node, const std::string& what) const {
    throw ConfigError(fmt::format("{}:{}: {}", origin_, node.source().begin.line, what));
  }

 private:
  const toml::node* Get(const char* key) const { return table_ == nullptr ? nullptr : table_->get(key); }

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
  std::string name_;
  const std::string& origin_;
};

}  // namespace edsp
