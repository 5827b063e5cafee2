#pragma once
// The UDP socket a vehicle model sends its packets to (docs/cueing.md, "The
// packet"), read without blocking: a node's cycle takes whatever came since
// the last one. Boost.Asio's socket, so the address may be IPv4 or IPv6.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace edsp {

class VehicleSocket {
 public:
  // Bound to `address`:`port` (port 0: one the system picks, see port()).
  // Throws std::runtime_error naming the address and why it cannot be bound.
  VehicleSocket(const std::string& address, std::uint16_t port);
  ~VehicleSocket();
  VehicleSocket(const VehicleSocket&) = delete;
  VehicleSocket& operator=(const VehicleSocket&) = delete;

  std::uint16_t port() const;
  // Each datagram waiting, in the order it came, to `take`; their count.
  // A datagram longer than any packet is passed cut to the buffer (the
  // parser refuses it by its size).
  int Drain(const std::function<void(const std::uint8_t* data, std::size_t size)>& take);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace edsp
