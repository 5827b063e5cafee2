#include "send_command.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <fmt/format.h>

#include "edsp/channels.h"
#include "edsp/cueing/manoeuvre.h"
#include "edsp/cueing/vehicle_message.h"
#include "edsp/cueing/vehicle_packet.h"
#include "edsp/node/group_file.h"
#include "edsp/node/runtime.h"
#include "edsp/node/session_discovery.h"
#include "edsp/transport/bus.h"
#include "live_command.h"

namespace edsp {

namespace {

CueCommand AfterCommand(const std::string& after) {
  if (after == "disengage" || after == "silence") return CueCommand::kDisengage;
  if (after == "estop") return CueCommand::kEStop;
  if (after == "freeze") return CueCommand::kFreeze;
  if (after == "engage") return CueCommand::kEngage;
  throw std::invalid_argument(fmt::format("--after \"{}\": one of disengage, silence, estop, freeze, engage", after));
}

// Sends one packet (throws std::runtime_error naming where it failed to go).
using PacketSender = std::function<void(const VehiclePacket&)>;

// The socket and its I/O context, torn down in that order.
struct UdpLink {
  explicit UdpLink(const boost::asio::ip::udp::endpoint& to) : socket(io, to.protocol()) {}
  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket;
};

PacketSender UdpSender(const std::string& to_text) {
  const HostPort to = ParseHostPort(to_text, "--to");
  boost::system::error_code error;
  const boost::asio::ip::udp::endpoint endpoint(boost::asio::ip::make_address(to.host, error), to.port);
  if (error) throw std::invalid_argument(fmt::format("--to \"{}\": not an IP address", to_text));
  auto link = std::make_shared<UdpLink>(endpoint);
  return [link, endpoint, to_text](const VehiclePacket& packet) {
    const auto bytes = EncodeVehiclePacket(packet);
    boost::system::error_code send_error;
    link->socket.send_to(boost::asio::buffer(bytes), endpoint, 0, send_error);
    if (send_error) throw std::runtime_error(fmt::format("sending to {}: {}", to_text, send_error.message()));
  };
}

std::int64_t SessionToAddress(const SendOptions& options, Bus& bus) {
  if (options.session == "auto") return DiscoverSession(bus, 5.0);
  std::size_t used = 0;
  long long id = -1;
  try {
    id = std::stoll(options.session, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != options.session.size() || id < 0) {
    throw std::invalid_argument(fmt::format("--session-id \"{}\": a non-negative integer or auto", options.session));
  }
  return id;
}

// The bus and its publisher, torn down in that order's reverse.
struct VehicleBus {
  explicit VehicleBus(const TransportConfig& transport)
      : bus(transport), out(bus.Advertise<vehicle_motion_t>(channel::kVehicle)) {}
  Bus bus;
  Bus::Publisher<vehicle_motion_t> out;
};

// EDSP_VEHICLE on the group's bus, over LCM: a host's samples come from
// outside the group's shared memory.
PacketSender BusSender(const SendOptions& options) {
  TransportConfig transport = options.group_path.empty() ? TransportConfig{} : LoadTransportConfig(options.group_path);
  if (!options.lcm_url.empty()) transport.lcm_url = options.lcm_url;
  transport.channels.clear();
  auto link = std::make_shared<VehicleBus>(transport);
  const std::int64_t session = SessionToAddress(options, link->bus);
  std::fprintf(stderr, "edsp-cueing send: to %s, session %lld\n", channel::kVehicle, static_cast<long long>(session));
  return [link, session](const VehiclePacket& packet) {
    if (!link->out.Publish(VehicleMessage(packet, session, UtimeNow()))) {
      throw std::runtime_error(fmt::format("publishing on {}: the bus refused it", channel::kVehicle));
    }
  };
}

}  // namespace

int RunSend(const SendOptions& options) {
  const Manoeuvre manoeuvre = LoadManoeuvre(options.manoeuvre_path);
  const CueCommand after = AfterCommand(options.after);
  if (options.to != "lcm" && (!options.group_path.empty() || !options.lcm_url.empty() || options.session != "auto")) {
    throw std::invalid_argument(
        fmt::format("--group, --lcm-url and --session-id address the bus: give --to lcm, not --to {}", options.to));
  }
  const PacketSender send = options.to == "lcm" ? BusSender(options) : UdpSender(options.to);
  std::ofstream sent_log;
  if (!options.sent_log_path.empty()) {
    sent_log.open(options.sent_log_path);
    if (!sent_log) throw std::runtime_error(fmt::format("--sent-log {}: cannot be written", options.sent_log_path));
    sent_log << "sequence,sent_utime\n";
  }

  const double period_s = 1.0 / options.rate_hz;
  const double end_s = options.lead_s + manoeuvre.duration_s + options.tail_s;
  const auto start = std::chrono::steady_clock::now();
  std::uint32_t sequence = 0;
  for (long k = 0;; ++k) {
    const double t = static_cast<double>(k) * period_s;
    if (t > end_s) break;
    std::this_thread::sleep_until(
        start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(t)));
    const bool in_tail = t > options.lead_s + manoeuvre.duration_s;
    if (in_tail && options.after == "silence") continue;
    VehiclePacket packet;
    packet.command = in_tail ? after : CueCommand::kEngage;
    packet.sequence = ++sequence;
    packet.time_s = t;
    const double local = t - options.lead_s;
    if (local >= 0.0 && local <= manoeuvre.duration_s) {
      const VehicleSample sample = manoeuvre.At(local);
      packet.specific_force_m_s2 = sample.specific_force_m_s2;
      packet.angular_velocity_rad_s = sample.angular_velocity_rad_s;
    }
    const std::int64_t sent_utime = UtimeNow();
    send(packet);
    if (sent_log.is_open()) sent_log << packet.sequence << ',' << sent_utime << '\n';
  }
  std::fprintf(stderr, "edsp-cueing send: %u packets of %s to %s\n", sequence, manoeuvre.name.c_str(),
               options.to.c_str());
  return 0;
}

}  // namespace edsp
