#pragma once
// edsp-gap's figures: a gnuplot script written beside its PNG (so a reader
// can restyle it) and run once. gnuplot-nox is one of deploy/edsp's packages.

#include <string>

namespace edsp::gap {

// Writes `dir`/`png`.gp (terminal, output and grid, then `script`) and runs
// gnuplot on it. Returns whether `dir`/`png` exists afterwards.
bool GnuplotPng(const std::string& dir, const std::string& png, const std::string& script);

}  // namespace edsp::gap
