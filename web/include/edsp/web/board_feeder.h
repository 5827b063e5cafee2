#pragma once
// The group's channels into the ChannelBoard, from edsp's Bus on a thread
// of its own: every EDSP_* channel on the route the group gives it (LCM, or
// a shared-memory ring read whole), as the logger reads them. It only
// reads: nothing edsp-web does reaches the 1 kHz path.

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "edsp/transport/bus.h"
#include "edsp/transport/transport_config.h"
#include "edsp/web/channel_board.h"

namespace edsp::web {

class BoardFeeder {
 public:
  // Throws TransportError naming a bus that cannot be opened.
  BoardFeeder(const TransportConfig& config, ChannelBoard* board);
  ~BoardFeeder();
  BoardFeeder(const BoardFeeder&) = delete;
  BoardFeeder& operator=(const BoardFeeder&) = delete;

  void Stop();
  // What the bus said when it failed ("" while it works).
  std::string error() const;

 private:
  void Run();

  std::unique_ptr<Bus> bus_;
  ChannelBoard* board_;
  std::atomic<bool> stopping_{false};
  mutable std::mutex mutex_;
  std::string error_;
  std::thread thread_;
};

}  // namespace edsp::web
