#include "edsp/cueing/vehicle_socket.h"

#include <array>
#include <stdexcept>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <fmt/format.h>

namespace edsp {

struct VehicleSocket::Impl {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket socket{io};
};

VehicleSocket::VehicleSocket(const std::string& address, std::uint16_t port) : impl_(std::make_unique<Impl>()) {
  boost::system::error_code error;
  const boost::asio::ip::address ip = boost::asio::ip::make_address(address, error);
  if (error) throw std::runtime_error(fmt::format("vehicle socket: \"{}\" is not an IP address", address));
  const boost::asio::ip::udp::endpoint endpoint(ip, port);
  impl_->socket.open(endpoint.protocol(), error);
  if (!error) impl_->socket.bind(endpoint, error);
  if (!error) impl_->socket.non_blocking(true, error);
  if (error) {
    throw std::runtime_error(fmt::format("vehicle socket: cannot bind UDP {}:{}: {}", address, port, error.message()));
  }
}

VehicleSocket::~VehicleSocket() = default;

std::uint16_t VehicleSocket::port() const { return impl_->socket.local_endpoint().port(); }

int VehicleSocket::Drain(const std::function<void(const std::uint8_t* data, std::size_t size)>& take) {
  // Larger than any packet by far: a longer datagram still arrives, and is refused by its size.
  std::array<std::uint8_t, 2048> buffer{};
  int count = 0;
  while (true) {
    boost::system::error_code error;
    boost::asio::ip::udp::endpoint from;
    const std::size_t size = impl_->socket.receive_from(boost::asio::buffer(buffer), from, 0, error);
    if (error == boost::asio::error::would_block || error == boost::asio::error::try_again) return count;
    if (error && error != boost::asio::error::message_size) return count;  // nothing more to read now
    take(buffer.data(), size);
    ++count;
  }
}

}  // namespace edsp
