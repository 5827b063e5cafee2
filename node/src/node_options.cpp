#include "edsp/node/node_options.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "edsp/node/group_file.h"
#include "edsp/transport/host_routes.h"

namespace edsp {

void AddNodeOptions(CLI::App* app, NodeOptions* o) {
  app->add_option("--config", o->config_path, "platform config (TOML)");
  app->add_option("--group", o->group_path, "deploy group file ([transport] routes)");
  app->add_option("--session-id", o->session_id, "launch session id");
  app->add_option("--member", o->member, "this process's member name in the group file");
  app->add_option("--lcm-url", o->lcm_url, "LCM URL (overrides the group file)");
}

TransportConfig TransportFor(const NodeOptions& o) {
  TransportConfig config =
      o.group_path.empty() ? TransportConfig{} : RoutesForMember(LoadTransportConfig(o.group_path), o.member);
  if (!o.lcm_url.empty()) config.lcm_url = o.lcm_url;
  return config;
}

std::string ReadTextFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace edsp
