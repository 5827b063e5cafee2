#pragma once
// Lets one thread sleep on shared-memory doorbells and a socket at once (a
// node with both LCM and shm inputs). A helper thread blocks in poll() on
// the socket and, when it becomes readable, rings a futex word that
// futex_waitv can wait on beside the segments' doorbells. It rings once per
// readiness and then waits until the owner has drained the socket
// (Drained()) before it polls again: it never spins.

#include <atomic>
#include <cstdint>
#include <thread>

namespace edsp {

class FdDoorbell {
 public:
  // Throws TransportError if the helper cannot be set up.
  explicit FdDoorbell(int fd);
  ~FdDoorbell();  // stops and joins the helper
  FdDoorbell(const FdDoorbell&) = delete;
  FdDoorbell& operator=(const FdDoorbell&) = delete;

  // The word to wait on: it changes whenever the socket became readable.
  std::atomic<std::uint32_t>* word() { return &bell_; }
  // The owner read what was ready: the helper may poll again.
  void Drained();

 private:
  void Run();

  int fd_;
  int stop_fd_ = -1;  // an eventfd that interrupts the helper's poll
  std::atomic<std::uint32_t> bell_{0};
  std::atomic<std::uint32_t> drained_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace edsp
