#pragma once
// A TOML file read as sections of typed values, every error a ConfigError
// naming the file, the line, the section and the key ("huang2021.toml:12:
// [drive] lead_m must be a number"). The one reader under every config edsp
// reads (platform, rig effects, drives, group file, transport routes); what a
// value means and its range stay with the module that owns it. toml++ stays
// inside this module: no header of it includes toml++.

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "edsp/config_file/config_error.h"

namespace edsp {

class ConfigSection;

// One parsed file; cheap to copy (its sections share it).
class ConfigFile {
 public:
  // A syntax error throws ConfigError naming `origin`, the line and the column.
  static ConfigFile Parse(const std::string& text, const std::string& origin);
  // The whole text of `path` (ConfigError naming it if unreadable).
  static std::string ReadText(const std::string& path);

  const std::string& origin() const;
  // The top-level table [name]: absent, a section whose present() is false.
  ConfigSection Section(const std::string& name) const;
  // The file's top level itself, as a section named "".
  ConfigSection Root() const;

 private:
  struct Document;
  explicit ConfigFile(std::shared_ptr<const Document> document);
  std::shared_ptr<const Document> document_;
};

// One table of the file, e.g. [drive], [rig.effects.backlash] or one
// [[member]]. Every read names the table and the key in its errors; a key
// that is absent gives the fallback. Numbers must be finite.
class ConfigSection {
 public:
  bool present() const { return table_ != nullptr; }
  // "drive", "rig.effects.backlash", "member#2".
  const std::string& name() const { return name_; }
  // How errors name it: "[drive]", "[[member]] #2".
  const std::string& label() const { return label_; }
  const std::string& origin() const;
  bool Has(std::string_view key) const;
  // The keys, sorted by name (a table's order in TOML carries no meaning).
  std::vector<std::string> Keys() const;

  // Every key must be one of `known`: a typo such as `lead = 0.01` must not
  // silently fall back to a default on a rig.
  void RejectUnknownKeys(std::initializer_list<const char*> known) const;

  std::string String(std::string_view key, const std::string& fallback) const;
  double Number(std::string_view key, double fallback) const;
  bool Bool(std::string_view key, bool fallback) const;
  std::int64_t Integer(std::string_view key, std::int64_t fallback) const;
  // An integer in [lo, hi].
  std::int64_t Integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) const;
  // An array of exactly `count` numbers.
  std::vector<double> Numbers(std::string_view key, std::size_t count) const;
  // Either one number or an array of `count`: what a per-leg value takes.
  std::vector<double> NumberOrNumbers(std::string_view key, std::size_t count, double fallback) const;
  // An array of `rows` arrays of `columns` numbers each, row by row.
  std::vector<std::vector<double>> Rows(std::string_view key, std::size_t rows, std::size_t columns) const;
  std::vector<std::string> Strings(std::string_view key) const;
  std::vector<std::int64_t> Integers(std::string_view key, std::int64_t lo, std::int64_t hi) const;

  // The table under `key` (absent: not present()), named "<name>.<key>".
  ConfigSection Table(std::string_view key) const;
  // Every table under this one with its key, sorted by key ([rig.effects.*]).
  std::vector<std::pair<std::string, ConfigSection>> Tables() const;
  // The array of tables under `key` ([[member]]), in file order.
  std::vector<ConfigSection> TableArray(std::string_view key) const;

  // Throws ConfigError at the line of `key` (of the section if `key` is
  // absent or empty): "<origin>:<line>: <what>".
  [[noreturn]] void Fail(std::string_view key, const std::string& what) const;
  // The same at the line of element `index` of the array `key`.
  [[noreturn]] void FailAtElement(std::string_view key, std::size_t index, const std::string& what) const;
  // The line of `key` (of the section if absent or empty).
  int Line(std::string_view key) const;
  // How many elements the array `key` has; -1 if it is absent or no array.
  long ArrayLength(std::string_view key) const;

 private:
  friend class ConfigFile;
  ConfigSection(std::shared_ptr<const void> document, const void* table, std::string name, std::string label,
                const std::string* origin, int line);
  [[noreturn]] void FailAtLine(int line, const std::string& what) const;
  const void* Node(std::string_view key) const;
  double ToNumber(const void* node, const std::string& what) const;

  // Opaque here so that toml++ stays in config_file.cpp: the parsed file,
  // kept alive, and the toml::table of this section (null when absent).
  std::shared_ptr<const void> document_;
  const void* table_ = nullptr;
  std::string name_;
  std::string label_;
  const std::string* origin_ = nullptr;
  int line_ = 0;
};

}  // namespace edsp
