#include "edsp/drives/modbus_drive_master.h"

#include <cerrno>
#include <cmath>

#include <fmt/format.h>
#include <modbus/modbus.h>

namespace edsp::cia402 {

ModbusDriveMaster::ModbusDriveMaster(std::string host, int port, double response_timeout_s)
    : host_(std::move(host)), port_(port), response_timeout_s_(response_timeout_s) {}

ModbusDriveMaster::~ModbusDriveMaster() { Disconnect(); }

std::string ModbusDriveMaster::endpoint() const { return fmt::format("modbus-tcp {}:{}", host_, port_); }

bool ModbusDriveMaster::Connect(std::string* error) {
  Disconnect();
  ctx_ = modbus_new_tcp(host_.c_str(), port_);
  if (ctx_ == nullptr) {
    *error = fmt::format("{}: {}", endpoint(), modbus_strerror(errno));
    return false;
  }
  // The whole answer within the response timeout: a byte timeout of the
  // same length keeps a half answer from stalling the cycle longer.
  const long timeout_us = std::lround(response_timeout_s_ * 1e6);
  const auto sec = static_cast<std::uint32_t>(timeout_us / 1000000);
  const auto usec = static_cast<std::uint32_t>(timeout_us % 1000000);
  modbus_set_response_timeout(ctx_, sec, usec);
  modbus_set_byte_timeout(ctx_, sec, usec);
  if (modbus_connect(ctx_) != 0) {
    // libmodbus leaves EINPROGRESS when its connect timed out: a server
    // whose backlog (of 1) is full, as a frozen one's soon is.
    *error = fmt::format("{}: cannot connect: {}", endpoint(),
                         errno == EINPROGRESS ? "no answer within the response timeout" : modbus_strerror(errno));
    Disconnect();
    return false;
  }
  return true;
}

void ModbusDriveMaster::Disconnect() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

bool ModbusDriveMaster::Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error) {
  if (!Connected(error)) return false;
  std::uint16_t out[modbus_map::kBlockRegisters];
  std::uint16_t in[modbus_map::kBlockRegisters];
  for (int d = 0; d < modbus_map::kDrives; ++d) {
    const modbus_map::DriveRegisters r = modbus_map::EncodeCommand(commands[static_cast<std::size_t>(d)]);
    std::copy(r.begin(), r.end(), out + d * modbus_map::kRegistersPerDrive);
  }
  const int read = modbus_write_and_read_registers(ctx_, modbus_map::kCommandAddress, modbus_map::kBlockRegisters, out,
                                                   modbus_map::kFeedbackAddress, modbus_map::kBlockRegisters, in);
  return TakeFeedback(read, in, "the drives' cycle (read/write of", feedback, error);
}

bool ModbusDriveMaster::ReadFeedback(CspFeedbacks* feedback, std::string* error) {
  if (!Connected(error)) return false;
  std::uint16_t in[modbus_map::kBlockRegisters];
  const int read = modbus_read_registers(ctx_, modbus_map::kFeedbackAddress, modbus_map::kBlockRegisters, in);
  return TakeFeedback(read, in, "reading the drives' feedback (read of", feedback, error);
}

bool ModbusDriveMaster::Connected(std::string* error) const {
  if (ctx_ != nullptr) return true;
  *error = endpoint() + ": not connected";
  return false;
}

bool ModbusDriveMaster::TakeFeedback(int read, const std::uint16_t* in, const char* request, CspFeedbacks* feedback,
                                     std::string* error) {
  if (read != modbus_map::kBlockRegisters) {
    *error = fmt::format("{}: {} {} registers) failed: {}", endpoint(), request, modbus_map::kBlockRegisters,
                         read < 0 ? modbus_strerror(errno) : "short answer");
    Disconnect();
    return false;
  }
  for (int d = 0; d < modbus_map::kDrives; ++d) {
    (*feedback)[static_cast<std::size_t>(d)] = modbus_map::DecodeFeedback(in + d * modbus_map::kRegistersPerDrive);
  }
  return true;
}

}  // namespace edsp::cia402
