// libFuzzer: the group file's one parser, as every member reads it (routes,
// host routing included) and as edsp-launch reads it (args expanded, then
// the systemd units of each host); and transport's [transport] reader alone,
// which the parser reaches only past valid members.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "edsp/node/group_file.h"
#include "edsp/transport/host_routes.h"
#include "group_file.h"
#include "systemd_units.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 16)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    (void)edsp::ParseTransportConfig(text, "fuzz.toml", {});
  } catch (const std::exception&) {
  }
  try {
    const edsp::TransportConfig config = edsp::ParseGroupFile(text, "fuzz.toml").transport;
    for (const auto& member : config.member_hosts) (void)edsp::RoutesForMember(config, member.first);
  } catch (const std::exception&) {
  }
  static const std::string path = "/tmp/edsp_fuzz_group_" + std::to_string(::getpid()) + ".toml";
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    const edsp::GroupSpec group = edsp::LoadGroupFile(path);
    for (const std::string& host : group.MemberHosts())
      (void)edsp::MemberUnits(group, host, "/opt/edsp", "/opt/edsp/bin");
  } catch (const std::exception&) {
  }
  return 0;
}
