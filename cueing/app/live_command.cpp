#include "live_command.h"

#include <cstdio>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/cueing/cueing_loop.h"
#include "edsp/kinematics/config.h"
#include "edsp/kinematics/platform_model.h"
#include "edsp/timing_contract.h"

namespace edsp {

HostPort ParseHostPort(const std::string& text, const std::string& option) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon + 1 == text.size()) {
    throw std::invalid_argument(fmt::format("{} \"{}\": give ADDRESS:PORT", option, text));
  }
  HostPort out;
  out.host = text.substr(0, colon);
  if (out.host.size() >= 2 && out.host.front() == '[' && out.host.back() == ']') {
    out.host = out.host.substr(1, out.host.size() - 2);
  }
  std::size_t used = 0;
  int port = -1;
  try {
    port = std::stoi(text.substr(colon + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() - colon - 1 || port < 0 || port > 65535) {
    throw std::invalid_argument(fmt::format("{} \"{}\": the port must be 0…65535", option, text));
  }
  out.port = static_cast<std::uint16_t>(port);
  return out;
}

int RunLive(const LiveOptions& options) {
  const PlatformModel model(LoadConfigFile(options.node.config_path));
  const CueingConfig config = LoadCueingConfig(options.cueing_path);
  const double stack_hz = 1e6 / static_cast<double>(timing::kCycleUs);
  if (config.rate_hz != stack_hz) {
    throw std::invalid_argument(fmt::format("{}: [cueing] rate_hz = {}: live cueing runs at the stack's {} Hz",
                                            options.cueing_path, config.rate_hz, stack_hz));
  }
  CueingSource source(config, model.home_pose().ToVector(), MakeCueingFilter(config.algorithm, model, config));
  if (options.input != "udp" && options.input != "lcm") {
    throw std::invalid_argument(fmt::format("--input \"{}\": udp or lcm", options.input));
  }
  std::unique_ptr<VehicleSocket> socket;
  CueingLoopOptions loop_options;
  loop_options.session_id = options.node.session_id;
  if (options.input == "lcm") {
    loop_options.vehicle_on_bus = true;
    loop_options.input_name = channel::kVehicle;
    std::fprintf(stderr, "edsp-cueing: vehicle samples on %s, session %lld\n", channel::kVehicle,
                 static_cast<long long>(options.node.session_id));
  } else if (!options.udp.empty()) {
    const HostPort at = ParseHostPort(options.udp, "--udp");
    socket = std::make_unique<VehicleSocket>(at.host, at.port);
    loop_options.input_name = fmt::format("UDP {}:{}", at.host, socket->port());
    std::fprintf(stderr, "edsp-cueing: vehicle packets on %s, session %lld\n", loop_options.input_name.c_str(),
                 static_cast<long long>(options.node.session_id));
  }
  InstallStopSignals();
  Bus bus(TransportFor(options.node));
  CueingLoop loop(bus, source, socket.get(), loop_options);
  RateClock clock(std::chrono::microseconds(timing::kCycleUs), kCueingPhase);
  loop.Run(clock, StopRequested);
  return 0;
}

}  // namespace edsp
