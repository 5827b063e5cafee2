#include "edsp/config_file/config_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

namespace edsp {

struct ConfigFile::Document {
  toml::table root;
  std::string origin;
};

namespace {

const toml::table* TableOf(const void* table) { return static_cast<const toml::table*>(table); }
const toml::node* NodeOf(const void* node) { return static_cast<const toml::node*>(node); }
int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

}  // namespace

ConfigFile::ConfigFile(std::shared_ptr<const Document> document) : document_(std::move(document)) {}

ConfigFile ConfigFile::Parse(const std::string& text, const std::string& origin) {
  auto document = std::make_shared<Document>();
  document->origin = origin;
  try {
    document->root = toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    throw ConfigError(
        fmt::format("{}:{}:{}: {}", origin, e.source().begin.line, e.source().begin.column, e.description()));
  }
  return ConfigFile(std::move(document));
}

std::string ConfigFile::ReadText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(fmt::format("{}: cannot open file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string& ConfigFile::origin() const { return document_->origin; }

ConfigSection ConfigFile::Root() const {
  return ConfigSection(document_, &document_->root, "", "[]", &document_->origin, 1);
}

ConfigSection ConfigFile::Section(const std::string& name) const { return Root().Table(name); }

ConfigSection::ConfigSection(std::shared_ptr<const void> document, const void* table, std::string name,
                             std::string label, const std::string* origin, int line)
    : document_(std::move(document)),
      table_(table),
      name_(std::move(name)),
      label_(std::move(label)),
      origin_(origin),
      line_(line) {}

const std::string& ConfigSection::origin() const { return *origin_; }

const void* ConfigSection::Node(std::string_view key) const {
  return table_ == nullptr ? nullptr : TableOf(table_)->get(key);
}

bool ConfigSection::Has(std::string_view key) const { return Node(key) != nullptr; }

std::vector<std::string> ConfigSection::Keys() const {
  std::vector<std::string> keys;
  if (table_ == nullptr) return keys;
  for (auto&& [key, node] : *TableOf(table_)) keys.emplace_back(key.str());
  return keys;
}

int ConfigSection::Line(std::string_view key) const {
  const void* node = key.empty() ? nullptr : Node(key);
  return node == nullptr ? line_ : LineOf(*NodeOf(node));
}

void ConfigSection::FailAtLine(int line, const std::string& what) const {
  throw ConfigError(fmt::format("{}:{}: {}", *origin_, line, what));
}

void ConfigSection::Fail(std::string_view key, const std::string& what) const { FailAtLine(Line(key), what); }

void ConfigSection::FailAtElement(std::string_view key, std::size_t index, const std::string& what) const {
  const toml::node* node = NodeOf(Node(key));
  const toml::array* array = node == nullptr ? nullptr : node->as_array();
  if (array == nullptr || index >= array->size()) Fail(key, what);
  FailAtLine(LineOf((*array)[index]), what);
}

long ConfigSection::ArrayLength(std::string_view key) const {
  const toml::node* node = NodeOf(Node(key));
  const toml::array* array = node == nullptr ? nullptr : node->as_array();
  return array == nullptr ? -1 : static_cast<long>(array->size());
}

void ConfigSection::RejectUnknownKeys(std::initializer_list<const char*> known) const {
  if (table_ == nullptr) return;
  for (auto&& [key, node] : *TableOf(table_)) {
    bool found = false;
    std::string list;
    for (const char* k : known) {
      found = found || key.str() == k;
      list += list.empty() ? k : fmt::format(", {}", k);
    }
    if (!found) FailAtLine(LineOf(node), fmt::format("unknown key {} {} (known keys: {})", label_, key.str(), list));
  }
}

std::string ConfigSection::String(std::string_view key, const std::string& fallback) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return fallback;
  if (!node->is_string()) FailAtLine(LineOf(*node), fmt::format("{} {} must be a string", label_, key));
  return *node->value<std::string>();
}

double ConfigSection::ToNumber(const void* value, const std::string& what) const {
  const toml::node& node = *NodeOf(value);
  if (!node.is_number()) FailAtLine(LineOf(node), fmt::format("{} {} must be a number", label_, what));
  const double number = *node.value<double>();
  if (!std::isfinite(number)) FailAtLine(LineOf(node), fmt::format("{} {} = {} must be finite", label_, what, number));
  return number;
}

double ConfigSection::Number(std::string_view key, double fallback) const {
  const void* node = Node(key);
  return node == nullptr ? fallback : ToNumber(node, std::string(key));
}

bool ConfigSection::Bool(std::string_view key, bool fallback) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return fallback;
  if (!node->is_boolean()) FailAtLine(LineOf(*node), fmt::format("{} {} must be true or false", label_, key));
  return *node->value<bool>();
}

std::int64_t ConfigSection::Integer(std::string_view key, std::int64_t fallback) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return fallback;
  if (!node->is_integer()) FailAtLine(LineOf(*node), fmt::format("{} {} must be an integer", label_, key));
  return *node->value<std::int64_t>();
}

std::int64_t ConfigSection::Integer(std::string_view key, std::int64_t fallback, std::int64_t lo,
                                    std::int64_t hi) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return fallback;
  const auto value = node->value<std::int64_t>();
  if (!node->is_integer() || *value < lo || *value > hi) {
    FailAtLine(LineOf(*node), fmt::format("{} {} must be an integer in {}..{}", label_, key, lo, hi));
  }
  return *value;
}

std::vector<double> ConfigSection::Numbers(std::string_view key, std::size_t count) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return {};
  const toml::array* values = node->as_array();
  if (values == nullptr || values->size() != count) {
    FailAtLine(LineOf(*node), fmt::format("{} {} must be an array of {} numbers", label_, key, count));
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(ToNumber(&(*values)[i], fmt::format("{}[{}]", key, i + 1)));
  return out;
}

std::vector<double> ConfigSection::NumberOrNumbers(std::string_view key, std::size_t count, double fallback) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return std::vector<double>(count, fallback);
  if (node->is_number()) return std::vector<double>(count, ToNumber(node, std::string(key)));
  const toml::array* values = node->as_array();
  if (values == nullptr || values->size() != count) {
    FailAtLine(LineOf(*node), fmt::format("{} {} must be a number or an array of {}", label_, key, count));
  }
  return Numbers(key, count);
}

std::vector<std::vector<double>> ConfigSection::Rows(std::string_view key, std::size_t rows,
                                                     std::size_t columns) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  if (array == nullptr || array->size() != rows) {
    FailAtLine(LineOf(*node), fmt::format("{} {} must be an array of {} rows", label_, key, rows));
  }
  std::vector<std::vector<double>> out;
  for (std::size_t r = 0; r < rows; ++r) {
    const toml::node& row = (*array)[r];
    const toml::array* values = row.as_array();
    if (values == nullptr || values->size() != columns) {
      FailAtLine(LineOf(row), fmt::format("{} {} row {} must be an array of {} numbers", label_, key, r + 1, columns));
    }
    std::vector<double> numbers;
    for (std::size_t c = 0; c < columns; ++c) {
      numbers.push_back(ToNumber(&(*values)[c], fmt::format("{} row {}", key, r + 1)));
    }
    out.push_back(std::move(numbers));
  }
  return out;
}

std::vector<std::string> ConfigSection::Strings(std::string_view key) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  if (array == nullptr) FailAtLine(LineOf(*node), fmt::format("{} {} must be an array of strings", label_, key));
  std::vector<std::string> out;
  for (const toml::node& element : *array) {
    if (!element.is_string()) {
      FailAtLine(LineOf(element), fmt::format("{} {} must be an array of strings", label_, key));
    }
    out.push_back(*element.value<std::string>());
  }
  return out;
}

std::vector<std::int64_t> ConfigSection::Integers(std::string_view key, std::int64_t lo, std::int64_t hi) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  const std::string what = fmt::format("{} {} must be an array of integers in {}..{}", label_, key, lo, hi);
  if (array == nullptr) FailAtLine(LineOf(*node), what);
  std::vector<std::int64_t> out;
  for (const toml::node& element : *array) {
    const auto value = element.value<std::int64_t>();
    if (!element.is_integer() || *value < lo || *value > hi) FailAtLine(LineOf(element), what);
    out.push_back(*value);
  }
  return out;
}

ConfigSection ConfigSection::Table(std::string_view key) const {
  const std::string name = name_.empty() ? std::string(key) : fmt::format("{}.{}", name_, key);
  const toml::node* node = NodeOf(Node(key));
  // Under an element of an array of tables, "[[member]] #1 env"; else "[member.env]".
  const bool in_element = label_.rfind("[[", 0) == 0;
  const std::string label = in_element ? fmt::format("{} {}", label_, key) : "[" + name + "]";
  if (node == nullptr) return ConfigSection(document_, nullptr, name, label, origin_, line_);
  if (!node->is_table()) FailAtLine(LineOf(*node), label + " must be a table");
  return ConfigSection(document_, node->as_table(), name, label, origin_, LineOf(*node));
}

std::vector<std::pair<std::string, ConfigSection>> ConfigSection::Tables() const {
  std::vector<std::pair<std::string, ConfigSection>> out;
  for (const std::string& key : Keys()) out.emplace_back(key, Table(key));
  return out;
}

std::vector<ConfigSection> ConfigSection::TableArray(std::string_view key) const {
  const toml::node* node = NodeOf(Node(key));
  if (node == nullptr) return {};
  const toml::array* array = node->as_array();
  if (array == nullptr || !array->is_array_of_tables()) {
    FailAtLine(LineOf(*node), fmt::format("[[{}]] must be an array of tables", key));
  }
  std::vector<ConfigSection> out;
  for (std::size_t i = 0; i < array->size(); ++i) {
    const toml::node& element = (*array)[i];
    out.push_back(ConfigSection(document_, element.as_table(), fmt::format("{}#{}", key, i + 1),
                                fmt::format("[[{}]] #{}", key, i + 1), origin_, LineOf(element)));
  }
  return out;
}

}  // namespace edsp
