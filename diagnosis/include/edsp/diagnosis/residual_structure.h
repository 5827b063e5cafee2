#pragma once
// What is left after the selected effects: white tracker noise, or structure
// nothing in the vocabulary explains. The verdict rests on evidence, not on
// the residual's size: the whiteness test must fail, and a clear share of the
// residual's variance must sit above its own white level (the spectrum's
// median: robust to a peak or a drift occupying a few frequencies), both in
// the fit (what the model cannot take up) and on runs held out of every fit
// (what it cannot predict). Held out alone is not enough: a rich model's
// parameter error leaves smooth, predictable error on a run it never saw,
// which the held-out shrink already reports. Structure between the runs
// counts too: white noise leaves each run's mean within its own scatter of
// zero, so runs that sit apart by more (a tracker stand settling, a target
// re-seated between runs), beyond chance (χ², 99.9%) and holding as much of
// the variance as an effect must cut to be selected, in and out of sample,
// are structure even where each run alone is white. Then the structure is
// described: its spectral peak (frequency, damping from the half-power
// width), what it follows (acceleration, velocity, direction, pose, time)
// and where it is largest.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "edsp/diagnosis/design.h"
#include "edsp/diagnosis/whiteness.h"

namespace edsp::gap {

struct ResidualStructure {
  Whiteness whiteness;            // of the held-out residual
  double structured_share = 0.0;  // of its variance above the white level
  Whiteness in_sample_whiteness;  // the same of the fit's own residual
  double in_sample_share = 0.0;
  double run_offset_share = 0.0;  // of its variance in the runs' means, beyond the noise's scatter
  double in_sample_run_offset_share = 0.0;
  bool runs_apart = false;              // the runs' means beyond chance, a clear share, in and out of sample
  bool structured = false;              // whiteness fails and the share is clear (or the runs sit apart),
                                        // in and out of sample
  double structured_rms_m = 0.0;        // point RMS of the structured part
  double dominant_hz = 0.0;             // the spectrum's peak (0: none)
  double damping = 0.0;                 // from the peak's half-power width (0: not resolved)
  std::string follows = "nothing";      // acceleration | velocity | direction | pose | time | nothing
  double follows_r2 = 0.0;              // share of the residual's variance that driver explains
  std::vector<std::string> largest_in;  // runs where its RMS is largest

  std::string Describe() const;
};

struct StructureOptions {
  double min_share = 0.10;  // of the variance above the white level, to count
  // Of the variance in the runs' means beyond the noise's scatter: the cut
  // in MSE that knowing each run's offset would give, so the bar an effect
  // must clear to be selected, not the spectral share's, whose white level
  // is itself an estimate. Diagnose sets it to DiagnoseOptions::min_cv_gain.
  double min_run_offset_share = 0.05;
  double min_driver_r2 = 0.15;  // a driver must explain this share to be named
};

// 3 values per sample of `d`: `in_sample` from the fit on every run,
// `heldout` each predicted by a fit that did not see the sample's run.
ResidualStructure AnalyseStructure(const Design& d, const Eigen::VectorXd& in_sample, const Eigen::VectorXd& heldout,
                                   const StructureOptions& options = {});

}  // namespace edsp::gap
