#include "edsp/drives/csp_master.h"

namespace edsp::cia402 {

CspCommand NextCspCommand(const CspFeedback& feedback, std::uint16_t previous,
                          std::optional<std::int32_t> wanted_counts, std::int32_t velocity_offset) {
  CspCommand command;
  const State state = StateOfStatusword(feedback.statusword);
  command.controlword = ControlwordTowardOperation(state, previous);
  command.mode_of_operation = kModeCyclicSynchronousPosition;
  const bool following = state == State::kOperationEnabled && wanted_counts.has_value();
  command.target_position = following ? *wanted_counts : feedback.position_actual;
  command.velocity_offset = following ? velocity_offset : 0;
  return command;
}

}  // namespace edsp::cia402
