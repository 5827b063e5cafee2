#pragma once
// The master's side of the shared-memory CSP image (csp_shm_image.h), as a
// CspLink: each exchange writes the RxPDOs and takes the TxPDOs the drives
// latched last, never waiting for them (a fieldbus master's inputs are one
// cycle old). Drives whose side is gone (its writer dead) or that latched
// nothing new for the response timeout fail the exchange, named; the
// image is looked for again at the next Connect, which takes only an
// image latched after it (drives that do not cycle are not connected).

#include <memory>
#include <string>

#include "edsp/drives/csp_link.h"
#include "edsp/transport/shm_channel.h"
#include "edsp/transport/watched_silence.h"

namespace edsp::cia402 {

class CspShmMaster final : public CspLink {
 public:
  CspShmMaster(std::string prefix, mode_t permissions, double response_timeout_s);

  bool Connect(std::string* error) override;
  bool connected() const override { return feedback_ != nullptr; }
  bool Exchange(const CspCommands& commands, CspFeedbacks* feedback, std::string* error) override;
  bool ReadFeedback(CspFeedbacks* feedback, std::string* error) override;
  void Disconnect() override { feedback_.reset(); }
  std::string endpoint() const override { return "cia402-shm " + prefix_; }

 private:
  // The newest TxPDOs into *feedback; false with *error when the drives'
  // side is gone or latched nothing for the response timeout.
  bool TakeLatest(CspFeedbacks* feedback, std::string* error);
  bool Fail(const std::string& why, std::string* error);
  bool DrivesLeft(std::string* error);

  std::string prefix_;
  mode_t permissions_;
  std::int64_t response_timeout_us_;
  std::unique_ptr<ShmWriter> commands_;
  std::unique_ptr<ShmReader> feedback_;
  CspFeedbacks last_{};
  WatchedSilence silence_;  // this master's looks since the newest image (steady clock)
  std::int64_t next_alive_check_utime_ = 0;
  bool has_image_ = false;  // an image taken since Connect: last_ is the drives'

  std::int64_t cycle_ = 0;
};

}  // namespace edsp::cia402
