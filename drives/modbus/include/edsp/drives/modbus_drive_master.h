#pragma once
// The master's side of edsp's Modbus TCP drives: one request per cycle
// (function 23, read/write multiple registers) writes the six drives'
// commands and reads their feedback. Every failure says which server and
// why; after one the connection is dropped and Connect tries again.

#include <array>
#include <cstdint>
#include <string>

#include "edsp/drives/modbus_register_map.h"

typedef struct _modbus modbus_t;

namespace edsp::cia402 {

using CspCommands = std::array<CspCommand, modbus_map::kDrives>;
using CspFeedbacks = std::array<CspFeedback, modbus_map::kDrives>;

class ModbusDriveMaster {
 public:
  ModbusDriveMaster(std::string host, int port, double response_timeout_s);
  ~ModbusDriveMaster();
  ModbusDriveMaster(const ModbusDriveMaster&) = delete;
  ModbusDriveMaster& operator=(const ModbusDriveMaster&) = delete;

  bool Connect(std::string* error);
  bool connected() const { return ctx_ != nullptr; }
  // One cycle; false with *error (and disconnected) when the exchange failed.
  bool Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error);
  // The feedback alone, writing nothing (what the drives are after a
  // reconnect, before any command is built on it).
  bool ReadFeedback(CspFeedbacks* feedback, std::string* error);
  void Disconnect();
  std::string endpoint() const;

 private:
  bool Connected(std::string* error) const;
  // The answer of one request (`read` registers into `in`): decoded, or
  // *error naming the request and why, and the connection dropped.
  bool TakeFeedback(int read, const std::uint16_t* in, const char* request, CspFeedbacks* feedback,
                    std::string* error);

  std::string host_;
  int port_;
  double response_timeout_s_;
  modbus_t* ctx_ = nullptr;
};

}  // namespace edsp::cia402
