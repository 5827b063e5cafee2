#include "group_file_editor.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <toml++/toml.h>

namespace edsp {

namespace {

template <typename T>
toml::array ArrayOf(const std::vector<T>& values) {
  toml::array array;
  for (const T& v : values) array.push_back(v);
  return array;
}

}  // namespace

struct GroupFileEditor::Document {
  std::string origin;  // the file loaded, for errors
  toml::table root;

  toml::table& Section(const std::string& name) {
    if (!root.contains(name)) root.insert(name, toml::table{});
    toml::table* section = root[name].as_table();
    if (section == nullptr) throw std::invalid_argument(origin + ": [" + name + "] is not a table");
    return *section;
  }

  toml::array& Members() {
    toml::array* members = root["member"].as_array();
    if (members == nullptr) throw std::invalid_argument(origin + ": no [[member]] entries");
    return *members;
  }

  std::size_t MemberIndex(const std::string& member) const {
    if (const toml::array* members = root["member"].as_array()) {
      for (std::size_t i = 0; i < members->size(); ++i) {
        const toml::table* t = (*members)[i].as_table();
        if (t != nullptr && t->get("name") != nullptr && t->get("name")->value_or(std::string()) == member) return i;
      }
    }
    throw std::invalid_argument(origin + ": no member \"" + member + "\"");
  }

  toml::table& Member(const std::string& member) { return *Members()[MemberIndex(member)].as_table(); }

  toml::array& ArgsOf(const std::string& member) {
    toml::table& m = Member(member);
    if (!m.contains("args")) m.insert("args", toml::array{});
    toml::array* args = m["args"].as_array();
    if (args == nullptr) throw std::invalid_argument(origin + ": member \"" + member + "\" args is not a list");
    return *args;
  }
};

GroupFileEditor::GroupFileEditor(std::unique_ptr<Document> document) : document_(std::move(document)) {}
GroupFileEditor::GroupFileEditor(const GroupFileEditor& other)
    : document_(other.document_ ? std::make_unique<Document>(*other.document_) : nullptr) {}
GroupFileEditor& GroupFileEditor::operator=(const GroupFileEditor& other) {
  if (this != &other) document_ = other.document_ ? std::make_unique<Document>(*other.document_) : nullptr;
  return *this;
}
GroupFileEditor::GroupFileEditor(GroupFileEditor&&) noexcept = default;
GroupFileEditor& GroupFileEditor::operator=(GroupFileEditor&&) noexcept = default;
GroupFileEditor::~GroupFileEditor() = default;

GroupFileEditor GroupFileEditor::Load(const std::string& path) {
  try {
    return GroupFileEditor(std::make_unique<Document>(Document{path, toml::parse_file(path)}));
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}:{}:{}: {}", path, e.source().begin.line, e.source().begin.column, e.description()));
  }
}

GroupFileEditor& GroupFileEditor::SetGroup(const std::string& key, const std::string& value) {
  document_->Section("group").insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetGroup(const std::string& key, std::int64_t value) {
  document_->Section("group").insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetTransport(const std::string& key, const std::string& value) {
  document_->Section("transport").insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetChannel(const std::string& channel, const std::string& key,
                                             const std::string& value) {
  toml::table& transport = document_->Section("transport");
  if (!transport.contains("channels")) transport.insert("channels", toml::table{});
  toml::table* channels = transport["channels"].as_table();
  if (channels == nullptr) throw std::invalid_argument(document_->origin + ": [transport.channels] is not a table");
  if (!channels->contains(channel)) channels->insert(channel, toml::table{});
  toml::table* route = channels->get_as<toml::table>(channel);
  if (route == nullptr)
    throw std::invalid_argument(document_->origin + ": [transport.channels." + channel + "] is not a table");
  route->insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetChannel(const std::string& channel, const std::string& key, std::int64_t value) {
  SetChannel(channel, key, std::string());  // makes and checks the tables
  document_->Section("transport")["channels"][channel].as_table()->insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetHost(const std::string& host, const std::string& interface) {
  toml::table& hosts = document_->Section("hosts");
  if (!hosts.contains(host)) hosts.insert(host, toml::table{});
  toml::table* section = hosts.get_as<toml::table>(host);
  if (section == nullptr) throw std::invalid_argument(document_->origin + ": [hosts." + host + "] is not a table");
  section->insert_or_assign("interface", interface);
  return *this;
}

GroupFileEditor& GroupFileEditor::RemoveHosts() {
  document_->root.erase("hosts");
  return *this;
}

GroupFileEditor& GroupFileEditor::SetArg(const std::string& member, const std::string& flag, const std::string& value) {
  toml::array& args = document_->ArgsOf(member);
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i].value_or(std::string()) != flag) continue;
    if (i + 1 < args.size()) {
      args.replace(args.cbegin() + static_cast<std::ptrdiff_t>(i + 1), value);
    } else {
      args.push_back(value);  // the flag ended the list without its value
    }
    return *this;
  }
  args.push_back(flag);
  args.push_back(value);
  return *this;
}

GroupFileEditor& GroupFileEditor::RemoveArg(const std::string& member, const std::string& flag) {
  toml::array& args = document_->ArgsOf(member);
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i].value_or(std::string()) != flag) continue;
    const auto at = args.cbegin() + static_cast<std::ptrdiff_t>(i);
    args.erase(at, i + 1 < args.size() ? at + 2 : at + 1);
    return *this;
  }
  return *this;
}

GroupFileEditor& GroupFileEditor::AppendArgs(const std::string& member, const std::vector<std::string>& more) {
  toml::array& args = document_->ArgsOf(member);
  for (const std::string& a : more) args.push_back(a);
  return *this;
}

GroupFileEditor& GroupFileEditor::ReplaceArgs(const std::string& member, const std::vector<std::string>& args) {
  document_->Member(member).insert_or_assign("args", ArrayOf(args));
  return *this;
}

GroupFileEditor& GroupFileEditor::SetMember(const std::string& member, const std::string& key,
                                            const std::string& value) {
  document_->Member(member).insert_or_assign(key, value);
  return *this;
}

GroupFileEditor& GroupFileEditor::SetMember(const std::string& member, const std::string& key, std::int64_t value) {
  document_->Member(member).insert_or_assign(key, value);
  return *this;
}

template <typename T>
GroupFileEditor& GroupFileEditor::SetList(const std::string& member, const std::string& key,
                                          const std::vector<T>& values) {
  if (values.empty()) {
    document_->Member(member).erase(key);
  } else {
    document_->Member(member).insert_or_assign(key, ArrayOf(values));
  }
  return *this;
}

GroupFileEditor& GroupFileEditor::SetMemberList(const std::string& member, const std::string& key,
                                                const std::vector<std::int64_t>& values) {
  return SetList(member, key, values);
}

GroupFileEditor& GroupFileEditor::SetMemberList(const std::string& member, const std::string& key,
                                                const std::vector<std::string>& values) {
  return SetList(member, key, values);
}

GroupFileEditor& GroupFileEditor::InsertMember(const std::string& after, const std::string& name,
                                               const std::string& command, const std::vector<std::string>& args) {
  const std::size_t at = document_->MemberIndex(after) + 1;
  toml::table member;
  member.insert("name", name);
  member.insert("command", command);
  member.insert("args", ArrayOf(args));
  toml::array& members = document_->Members();
  members.insert(members.cbegin() + static_cast<std::ptrdiff_t>(at), std::move(member));
  return *this;
}

GroupFileEditor& GroupFileEditor::RemoveMember(const std::string& member) {
  toml::array& members = document_->Members();
  members.erase(members.cbegin() + static_cast<std::ptrdiff_t>(document_->MemberIndex(member)));
  return *this;
}

std::vector<std::string> GroupFileEditor::Args(const std::string& member) const {
  std::vector<std::string> out;
  const std::size_t index = document_->MemberIndex(member);  // throws unless the member is there
  const toml::table* m = document_->root["member"][index].as_table();
  if (const toml::array* args = m != nullptr ? m->get_as<toml::array>("args") : nullptr) {
    for (const toml::node& a : *args) out.push_back(a.value_or(std::string()));
  }
  return out;
}

std::string GroupFileEditor::Text() const {
  std::ostringstream out;
  out << "# from " << document_->origin << " (GroupFileEditor)\n" << document_->root << "\n";
  return out.str();
}

GroupSpec GroupFileEditor::Write(const std::string& path) const {
  {
    std::ofstream out(path);
    out << Text();
    if (!out) throw std::runtime_error(path + ": cannot write the group file");
  }
  return LoadGroupFile(path);
}

std::vector<std::string> ParseArgList(const std::string& items) {
  toml::table parsed;
  try {
    parsed = toml::parse("args = [" + items + "]");
  } catch (const toml::parse_error& e) {
    throw std::invalid_argument("argument list [" + items + "]: " + std::string(e.description()));
  }
  std::vector<std::string> args;
  for (const toml::node& a : *parsed["args"].as_array()) {
    const std::optional<std::string> text = a.value<std::string>();
    if (!text) throw std::invalid_argument("argument list [" + items + "]: every item must be a string");
    args.push_back(*text);
  }
  return args;
}

}  // namespace edsp
