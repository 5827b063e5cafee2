#include "send_command.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <fmt/format.h>

#include "edsp/cueing/manoeuvre.h"
#include "edsp/cueing/vehicle_packet.h"
#include "edsp/node/runtime.h"
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

}  // namespace

int RunSend(const SendOptions& options) {
  const Manoeuvre manoeuvre = LoadManoeuvre(options.manoeuvre_path);
  const CueCommand after = AfterCommand(options.after);
  const HostPort to = ParseHostPort(options.to, "--to");
  boost::asio::io_context io;
  boost::system::error_code error;
  const boost::asio::ip::udp::endpoint endpoint(boost::asio::ip::make_address(to.host, error), to.port);
  if (error) throw std::invalid_argument(fmt::format("--to \"{}\": not an IP address", options.to));
  boost::asio::ip::udp::socket socket(io, endpoint.protocol());
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
    const auto bytes = EncodeVehiclePacket(packet);
    const std::int64_t sent_utime = UtimeNow();
    socket.send_to(boost::asio::buffer(bytes), endpoint, 0, error);
    if (error) throw std::runtime_error(fmt::format("sending to {}: {}", options.to, error.message()));
    if (sent_log.is_open()) sent_log << packet.sequence << ',' << sent_utime << '\n';
  }
  std::fprintf(stderr, "edsp-cueing send: %u packets of %s to %s\n", sequence, manoeuvre.name.c_str(),
               options.to.c_str());
  return 0;
}

}  // namespace edsp
