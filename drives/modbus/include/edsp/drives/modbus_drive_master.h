#pragma once
// The master's side of edsp's Modbus TCP drives: one request per cycle
// (function 23, read/write multiple registers) writes the six drives'
// commands and reads their feedback. Every failure says which server and
// why; after one the connection is dropped and Connect tries again.

#include <array>
#include <cstdint>
#include <string>

#include "edsp/drives/csp_link.h"
#include "edsp/drives/modbus_register_map.h"

typedef struct _modbus modbus_t;

namespace edsp::cia402 {

static_assert(modbus_map::kDrives == kCabinetDrives, "one register block per drive of a cabinet");

class ModbusDriveMaster final : public CspLink {
 public:
  ModbusDriveMaster(std::string host, int port, double response_timeout_s);
  ~ModbusDriveMaster() override;
  ModbusDriveMaster(const ModbusDriveMaster&) = delete;
  ModbusDriveMaster& operator=(const ModbusDriveMaster&) = delete;

  bool Connect(std::string* error) override;
  bool connected() const override { return ctx_ != nullptr; }
  bool Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error) override;
  bool ReadFeedback(CspFeedbacks* feedback, std::string* error) override;
  void Disconnect() override;
  std::string endpoint() const override;

 private:
  bool Connected(std::string* error) const;
  // The answer of one request (`read` registers into `in`): decoded, or
  // *error naming the request and why, and the connection dropped.
  bool TakeFeedback(int read, const std::uint16_t* in, const char* request, CspFeedbacks* feedback, std::string* error);

  std::string host_;
  int port_;
  double response_timeout_s_;
  modbus_t* ctx_ = nullptr;
};

}  // namespace edsp::cia402
