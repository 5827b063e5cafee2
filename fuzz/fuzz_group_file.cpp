// libFuzzer: the process-group file parser (edsp-launch) and the [transport]
// routes every node reads from the same file, host routing included.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "edsp/transport/host_routes.h"
#include "edsp/transport/transport_config.h"
#include "group_file.h"
#include "systemd_units.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 16)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const edsp::TransportConfig config = edsp::ParseTransportConfig(text, "fuzz.toml");
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
