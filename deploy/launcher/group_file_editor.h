#pragma once
// A shipped group file (deploy/groups/*.toml) as the start of another: the
// multi-process tests, the fault matrix, the multi-host runs and the stack
// benchmark load the group users launch and change only what they must (a
// session, an argument, a host, one more member), so each group is
// described once. The result is written as TOML and checked as edsp-launch
// checks any group file (LoadGroupFile).
//
//   GroupFileEditor::Load("deploy/groups/sim.toml")
//       .SetGroup("session_id", 77)
//       .SetArg("kinematics", "--pr-mode", "none")
//       .Write(dir + "/group.toml");

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "group_file.h"

namespace edsp {

class GroupFileEditor {
 public:
  // Throws std::runtime_error naming the file (unreadable, not TOML).
  static GroupFileEditor Load(const std::string& path);
  // Copies are independent documents: a group edited two ways from one load.
  GroupFileEditor(const GroupFileEditor& other);
  GroupFileEditor& operator=(const GroupFileEditor& other);
  GroupFileEditor(GroupFileEditor&&) noexcept;
  GroupFileEditor& operator=(GroupFileEditor&&) noexcept;
  ~GroupFileEditor();

  // [group] keys (name, config, session_id) and [transport] keys (lcm_url,
  // shm_prefix, ...); [transport.channels.CHANNEL] keys (path, writer, ...).
  GroupFileEditor& SetGroup(const std::string& key, const std::string& value);
  GroupFileEditor& SetGroup(const std::string& key, std::int64_t value);
  GroupFileEditor& SetTransport(const std::string& key, const std::string& value);
  GroupFileEditor& SetChannel(const std::string& channel, const std::string& key, const std::string& value);
  GroupFileEditor& SetChannel(const std::string& channel, const std::string& key, std::int64_t value);
  // [hosts.NAME] interface; RemoveHosts drops every [hosts.*] section.
  GroupFileEditor& SetHost(const std::string& host, const std::string& interface);
  GroupFileEditor& RemoveHosts();

  // A member's arguments. SetArg: the value after `flag` if the member has
  // the flag, else `flag value` appended. The others append to, or replace,
  // the whole list. Every member call throws std::invalid_argument naming
  // a member the file does not have.
  GroupFileEditor& SetArg(const std::string& member, const std::string& flag, const std::string& value);
  // The flag and the value after it, if the member has the flag.
  GroupFileEditor& RemoveArg(const std::string& member, const std::string& flag);
  GroupFileEditor& AppendArgs(const std::string& member, const std::vector<std::string>& args);
  GroupFileEditor& ReplaceArgs(const std::string& member, const std::vector<std::string>& args);
  // A member's other keys: host, restart (strings); start_delay_ms,
  // realtime_priority, max_restarts (integers); cpus, requires (lists; an
  // empty list removes the key).
  GroupFileEditor& SetMember(const std::string& member, const std::string& key, const std::string& value);
  GroupFileEditor& SetMember(const std::string& member, const std::string& key, std::int64_t value);
  GroupFileEditor& SetMemberList(const std::string& member, const std::string& key,
                                 const std::vector<std::int64_t>& values);
  GroupFileEditor& SetMemberList(const std::string& member, const std::string& key,
                                 const std::vector<std::string>& values);
  // One more member, started after `after`, with its command and arguments
  // (its other keys through SetMember).
  GroupFileEditor& InsertMember(const std::string& after, const std::string& name, const std::string& command,
                                const std::vector<std::string>& args);
  GroupFileEditor& RemoveMember(const std::string& member);

  std::vector<std::string> Args(const std::string& member) const;
  std::string Text() const;
  // Writes the group to `path` and loads it as edsp-launch will; throws
  // std::runtime_error naming the file and what is wrong.
  GroupSpec Write(const std::string& path) const;

 private:
  // The file as parsed, and the edits on it: toml++ stays in the .cpp.
  struct Document;
  explicit GroupFileEditor(std::unique_ptr<Document> document);
  template <typename T>
  GroupFileEditor& SetList(const std::string& member, const std::string& key, const std::vector<T>& values);

  std::unique_ptr<Document> document_;
};

// The strings of a TOML array's items written out (`"--motions", "Lz"`),
// as test helpers and group templates pass argument lists; throws
// std::invalid_argument naming the text when it is not a list of strings.
std::vector<std::string> ParseArgList(const std::string& items);

}  // namespace edsp
