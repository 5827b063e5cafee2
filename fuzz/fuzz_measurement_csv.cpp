// libFuzzer: the measurement CSV reader of interfaces.md §3 (what a real
// tracker's export goes through). Errors must name file, line and column.
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "edsp/diagnosis/measurement_data.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 18)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const edsp::gap::MeasurementData m = edsp::gap::ParseMeasurementCsv(text, "fuzz.csv");
    (void)edsp::gap::Decimated(m, 100.0);
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).find("fuzz.csv") == std::string::npos) std::abort();  // unnamed error
  }
  return 0;
}
