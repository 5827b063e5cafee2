#include "edsp/sim/sampled_runs.h"

#include <cmath>
#include <memory>

#include "edsp/planner/motion_library.h"

namespace edsp {

namespace {

std::string RunOfSegment(const std::string& segment) { return segment.substr(0, segment.find('/')); }

}  // namespace

std::vector<SampledRun> SampleRuns(const PlatformModel& model, const std::vector<std::string>& names,
                                   const PaperMotionOptions& paper, double rate_hz) {
  const std::unique_ptr<TrajectorySequence> sequence = MotionSequence(model, names, paper);
  std::vector<SampledRun> runs;
  for (int k = 0; k < sequence->size();) {
    SampledRun run;
    run.name = RunOfSegment(sequence->SegmentName(k));
    const double begin_s = sequence->SegmentStart(k);
    while (k < sequence->size() && RunOfSegment(sequence->SegmentName(k)) == run.name) ++k;
    const double end_s = k < sequence->size() ? sequence->SegmentStart(k) : sequence->duration_s();
    const auto steps = static_cast<int>(std::round((end_s - begin_s) * rate_hz));
    for (int i = 0; i <= steps; ++i) run.samples.push_back(sequence->Sample(begin_s + i / rate_hz));
    runs.push_back(std::move(run));
  }
  return runs;
}

}  // namespace edsp
