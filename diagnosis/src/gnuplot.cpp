#include "edsp/diagnosis/gnuplot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

namespace edsp::gap {

bool GnuplotPng(const std::string& dir, const std::string& png, const std::string& script) {
  const std::string path = dir + "/" + png + ".gp";
  std::filesystem::remove(dir + "/" + png);  // a plot left from an earlier run is not this one
  std::ofstream(path) << "set terminal pngcairo size 900,500\nset output '" << dir << "/" << png << "'\n"
                      << "set grid\n"
                      << script;
  std::system(fmt::format("gnuplot '{}' 2>/dev/null", path).c_str());
  return std::filesystem::exists(dir + "/" + png);
}

}  // namespace edsp::gap
