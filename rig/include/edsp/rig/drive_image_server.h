#pragma once
// The drives' side of the process image (drive_io/drive_process_image.h) as
// the virtual rig serves it: the feedback ring it writes every cycle, the
// commands it reads, and what a predecessor killed mid-run left there.

#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "edsp/drive_io/drive_process_image.h"
#include "edsp/rig/virtual_rig.h"
#include "edsp/transport/shm_channel.h"

namespace edsp {

class DriveImageServer {
 public:
  // Claims the feedback ring <prefix>.drive.feedback. Throws
  // std::runtime_error naming it (another live rig holds it, ...).
  DriveImageServer(const std::string& prefix, mode_t permissions);

  // The commands that arrived since the last call, in order, as many as the
  // ring still holds (a rig that woke late replays them): appended to
  // *commands. None while no bridge made the command ring.
  void NewCommands(std::vector<DriveImageCommand>* commands);
  void PublishFeedback(const DriveFeedback& feedback, std::int64_t utime, std::int64_t cycle);
  std::string command_segment() const { return DriveCommandSegment(prefix_); }
  std::string feedback_segment() const { return DriveFeedbackSegment(prefix_); }

 private:
  std::string prefix_;
  mode_t mode_;
  std::unique_ptr<ShmWriter> feedback_;
  std::unique_ptr<ShmReader> commands_;
};

// What a start found in the image a predecessor left.
struct ImageRestore {
  bool restored = false;  // the rig continues from the drives' last feedback
  std::string note;       // what happened, for the log; empty: nothing was there
};

// A predecessor killed mid-run left its last drive feedback in the image:
// the motors are still there (absolute encoders), so the rig continues from
// them. Call before a DriveImageServer claims the ring. A live rig's ring,
// or none, is left alone (note empty).
ImageRestore RestoreFromImage(const std::string& prefix, mode_t permissions, VirtualRig* rig);

}  // namespace edsp
