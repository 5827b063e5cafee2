#include "edsp/drives/modbus_drive_server.h"

#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <stdexcept>

#include <fmt/format.h>
#include <modbus/modbus.h>

namespace edsp::cia402 {
namespace {

constexpr int kFunctionWriteSingle = 0x06;
constexpr int kFunctionWriteMultiple = 0x10;
constexpr int kFunctionReadWriteMultiple = 0x17;
constexpr int kFunctionOffset = 7;  // after the MBAP header

std::int64_t WallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int BoundPort(int socket) {
  sockaddr_in address{};
  socklen_t length = sizeof(address);
  if (::getsockname(socket, reinterpret_cast<sockaddr*>(&address), &length) != 0) return -1;
  return ntohs(address.sin_port);
}

}  // namespace

ModbusDriveServer::ModbusDriveServer(const DriveServerOptions& options, std::unique_ptr<CspAxes> axes)
    : options_(options), cabinet_(options.drive, std::move(axes)) {
  static_assert(modbus_map::kDrives == kCabinetDrives, "one cabinet drive per drive of the map");
  const std::string where = fmt::format("{}:{}", options.host, options.port);
  if (!(options.cycle_s > 0.0 && options.cycle_s <= 0.1)) {
    throw std::runtime_error(fmt::format("drive cycle {} s: must be in (0, 0.1]", options.cycle_s));
  }
  ctx_ = modbus_new_tcp(options.host.c_str(), options.port);
  if (ctx_ == nullptr) throw std::runtime_error(fmt::format("modbus-tcp {}: {}", where, modbus_strerror(errno)));
  mapping_ = modbus_mapping_new(0, 0, modbus_map::kRegisterCount, 0);
  listener_ = mapping_ != nullptr ? modbus_tcp_listen(ctx_, 1) : -1;
  if (listener_ < 0) {
    const std::string why = modbus_strerror(errno);
    if (mapping_ != nullptr) modbus_mapping_free(mapping_);
    modbus_free(ctx_);
    throw std::runtime_error(fmt::format("modbus-tcp {}: cannot listen: {}", where, why));
  }
  port_ = BoundPort(listener_);
  // A client that sends half a request must not stop the drives' clock.
  modbus_set_indication_timeout(ctx_, 0, 100000);
  Latch();  // the feedback block holds the drives' state before the first request
}

ModbusDriveServer::~ModbusDriveServer() {
  CloseClient();
  if (listener_ >= 0) ::close(listener_);
  modbus_mapping_free(mapping_);
  modbus_free(ctx_);
}

void ModbusDriveServer::Latch() {
  for (int d = 0; d < modbus_map::kDrives; ++d) {
    const modbus_map::DriveRegisters r = modbus_map::EncodeFeedback(cabinet_.latched()[static_cast<std::size_t>(d)]);
    std::copy(r.begin(), r.end(),
              mapping_->tab_registers + modbus_map::kFeedbackAddress + d * modbus_map::kRegistersPerDrive);
  }
}

void ModbusDriveServer::CloseClient() {
  if (client_ >= 0) ::close(client_);
  client_ = -1;
}

void ModbusDriveServer::Serve(int client) {
  std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
  modbus_set_socket(ctx_, client);
  const int length = modbus_receive(ctx_, query);
  if (length <= 0) {  // the master closed or sent garbage: drop it, wait for the next
    CloseClient();
    return;
  }
  if (modbus_reply(ctx_, query, length, mapping_) < 0) {
    CloseClient();
    return;
  }
  ++requests_;
  const int function = query[kFunctionOffset];
  if (function == kFunctionWriteSingle || function == kFunctionWriteMultiple ||
      function == kFunctionReadWriteMultiple) {
    CspCommands commands;
    for (int d = 0; d < modbus_map::kDrives; ++d) {
      commands[static_cast<std::size_t>(d)] = modbus_map::DecodeCommand(
          mapping_->tab_registers + modbus_map::kCommandAddress + d * modbus_map::kRegistersPerDrive);
    }
    cabinet_.Command(commands, WallUtime());
  }
}

void ModbusDriveServer::Run(const std::function<bool()>& stop) {
  CycleSchedule schedule(options_.cycle_s);
  while (!stop()) {
    const auto now = CycleSchedule::Clock::now();
    // The drives' clock first (CycleSchedule: one step for a late wake).
    const std::int64_t due = schedule.Due(now);
    if (due > 0 && cabinet_.Tick(options_.cycle_s * static_cast<double>(due))) Latch();
    pollfd fds[2] = {{listener_, POLLIN, 0}, {client_, POLLIN, 0}};
    const auto wait = std::chrono::duration_cast<std::chrono::nanoseconds>(schedule.next_tick() - now);
    const timespec timeout{static_cast<time_t>(wait.count() / 1000000000),
                           static_cast<long>(wait.count() % 1000000000)};
    const int ready = ::ppoll(fds, client_ >= 0 ? 2 : 1, &timeout, nullptr);
    if (ready <= 0) continue;
    if ((fds[0].revents & POLLIN) != 0) {
      CloseClient();  // a new master replaces the old one (a restarted bridge)
      int listener = listener_;
      client_ = modbus_tcp_accept(ctx_, &listener);
      continue;  // fds[1] spoke of the old client, whose fd number the new one may reuse
    }
    if (client_ >= 0 && (fds[1].revents & (POLLIN | POLLHUP | POLLERR)) != 0) Serve(client_);
  }
}

}  // namespace edsp::cia402
