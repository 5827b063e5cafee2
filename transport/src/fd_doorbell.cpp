#include "edsp/transport/fd_doorbell.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "edsp/transport/error.h"
#include "edsp/transport/futex.h"

namespace edsp {

FdDoorbell::FdDoorbell(int fd) : fd_(fd), stop_fd_(::eventfd(0, EFD_CLOEXEC)) {
  if (stop_fd_ < 0) throw TransportError(std::string("eventfd: ") + std::strerror(errno));
  thread_ = std::thread([this] { Run(); });
}

FdDoorbell::~FdDoorbell() {
  stop_.store(true, std::memory_order_seq_cst);
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(stop_fd_, &one, sizeof one);
  drained_.fetch_add(1, std::memory_order_seq_cst);
  FutexWakeAll(&drained_);
  thread_.join();
  ::close(stop_fd_);
}

void FdDoorbell::Drained() {
  drained_.fetch_add(1, std::memory_order_seq_cst);
  FutexWakeAll(&drained_);
}

void FdDoorbell::Run() {
  std::uint32_t seen = drained_.load(std::memory_order_seq_cst);
  while (!stop_.load(std::memory_order_seq_cst)) {
    pollfd fds[2] = {{fd_, POLLIN, 0}, {stop_fd_, POLLIN, 0}};
    if (::poll(fds, 2, -1) < 0 && errno != EINTR) return;
    if (stop_.load(std::memory_order_seq_cst)) return;
    if ((fds[0].revents & (POLLIN | POLLERR | POLLHUP)) == 0) continue;
    bell_.fetch_add(1, std::memory_order_seq_cst);
    FutexWakeAll(&bell_);
    // The owner reads the socket on its own thread; until it has, the socket
    // stays readable and polling again would spin.
    while (!stop_.load(std::memory_order_seq_cst) && drained_.load(std::memory_order_seq_cst) == seen) {
      FutexWait(&drained_, seen, std::chrono::milliseconds(100));
    }
    seen = drained_.load(std::memory_order_seq_cst);
  }
}

}  // namespace edsp
