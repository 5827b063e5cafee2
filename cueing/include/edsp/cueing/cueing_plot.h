#pragma once
// A manoeuvre's figure: what the vehicle and the platform make a rider
// feel, channel by channel, through the vestibular models
// (cueing/vestibular.h), drawn by gnuplot (gnuplot-nox, one of deploy/edsp's
// packages) with its data and script beside it so it can be restyled.

#include <string>

#include "edsp/cueing/cueing_run.h"
#include "edsp/cueing/vestibular.h"

namespace edsp {

// Writes <dir>/<name>.dat (t_s, the vehicle's six perceived channels, the
// platform's six; fz less g), <name>.gp and <name>.png, titled with
// `algorithm` and the run's score; returns the PNG's path. Throws
// std::runtime_error naming the file it cannot write, or gnuplot's failure.
std::string PlotCueingRun(const CueingRun& run, const VestibularParameters& perception, const std::string& algorithm,
                          const std::string& dir, const std::string& name);

}  // namespace edsp
