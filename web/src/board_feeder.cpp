#include "edsp/web/board_feeder.h"

#include <chrono>
#include <exception>

#include "edsp/node/runtime.h"

namespace edsp::web {
namespace {
constexpr auto kHandleSlice = std::chrono::milliseconds(20);  // how soon Stop() is seen
}  // namespace

BoardFeeder::BoardFeeder(const TransportConfig& config, ChannelBoard* board)
    : bus_(std::make_unique<Bus>(config)), board_(board) {
  bus_->SubscribeRaw("EDSP_.*", [this](const std::string& channel, const std::uint8_t* data, std::uint32_t size) {
    board_->Post(channel, UtimeNow() * 1000, data, size);
  });
  thread_ = std::thread([this] { Run(); });
}

BoardFeeder::~BoardFeeder() { Stop(); }

void BoardFeeder::Stop() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

std::string BoardFeeder::error() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

void BoardFeeder::Run() {
  try {
    while (!stopping_) bus_->Handle(kHandleSlice);
  } catch (const std::exception& e) {
    const std::lock_guard<std::mutex> lock(mutex_);
    error_ = e.what();
  }
}

}  // namespace edsp::web
