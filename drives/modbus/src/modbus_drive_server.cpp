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
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch()).count();
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
  for (auto& pending : pending_faults_) pending.store(0);
  Tick(0.0);  // the feedback block holds the drives' state before the first request
}

ModbusDriveServer::~ModbusDriveServer() {
  CloseClient();
  if (listener_ >= 0) ::close(listener_);
  modbus_mapping_free(mapping_);
  modbus_free(ctx_);
}

void ModbusDriveServer::InjectFault(int index, std::uint16_t error_code) {
  if (index >= 0 && index < modbus_map::kDrives) pending_faults_[static_cast<std::size_t>(index)].store(error_code);
}

void ModbusDriveServer::Tick(double dt_s) {
  for (int d = 0; d < modbus_map::kDrives; ++d) {
    const std::uint16_t fault = pending_faults_[static_cast<std::size_t>(d)].exchange(0);
    if (fault != 0) cabinet_.InjectFault(d, fault);
  }
  cabinet_.Tick(dt_s);
  ++cycles_;  // wraps at 2^16, as the register does
  for (int d = 0; d < modbus_map::kDrives; ++d) {
    CspFeedback latched = cabinet_.Feedback(d);
    latched.cycle_count = cycles_;
    const modbus_map::DriveRegisters r = modbus_map::EncodeFeedback(latched);
    std::copy(r.begin(), r.end(), mapping_->tab_registers + modbus_map::kFeedbackAddress + d * modbus_map::kRegistersPerDrive);
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
  if (function == kFunctionWriteSingle || function == kFunctionWriteMultiple || function == kFunctionReadWriteMultiple) {
    std::array<CspCommand, kCabinetDrives> commands;
    for (int d = 0; d < modbus_map::kDrives; ++d) {
      commands[static_cast<std::size_t>(d)] = modbus_map::DecodeCommand(
          mapping_->tab_registers + modbus_map::kCommandAddress + d * modbus_map::kRegistersPerDrive);
    }
    cabinet_.Command(commands, WallUtime());
  }
}

void ModbusDriveServer::Run(const std::function<bool()>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto cycle = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options_.cycle_s));
  auto next_tick = Clock::now() + cycle;
  while (!stop()) {
    auto now = Clock::now();
    // The drives' clock first. After a late wake (the simulator stopped or
    // descheduled) every missed cycle is one step: the axes may be another
    // process's physics that lived through the stall in real time, and
    // replaying the missed cycles would command them the past (the last
    // target, while the fieldbus timeout had not yet run out in the replay).
    // One step sees the whole stall, as a real drive's watchdog would have.
    if (now >= next_tick) {
      const auto missed = (now - next_tick) / cycle + 1;
      if (!clock_stopped_.load()) Tick(options_.cycle_s * static_cast<double>(missed));
      next_tick += cycle * missed;
    }
    pollfd fds[2] = {{listener_, POLLIN, 0}, {client_, POLLIN, 0}};
    const auto wait = std::chrono::duration_cast<std::chrono::nanoseconds>(next_tick - now);
    const timespec timeout{static_cast<time_t>(wait.count() / 1000000000), static_cast<long>(wait.count() % 1000000000)};
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
