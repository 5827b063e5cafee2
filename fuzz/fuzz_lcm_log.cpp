// libFuzzer: the LCM log reader behind edsp-log and edsp-gap (a truncated,
// corrupted or foreign log): it reads up to the damage and says where.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "edsp/logger/log_reader.h"
#include "edsp/logger/log_summary.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 20)) return 0;
  static const std::string path = "/tmp/edsp_fuzz_log_" + std::to_string(::getpid()) + ".lcmlog";
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  try {
    edsp::LogReader reader(path);
    edsp::LogEvent event;
    std::int64_t events = 0;
    while (reader.Next(&event)) ++events;
    if (reader.damaged() && (reader.damage_offset() < 0 || reader.damage_offset() > static_cast<std::int64_t>(size))) {
      std::abort();  // damage must be placed inside the file
    }
    const edsp::LogSummary summary = edsp::SummarizeLog(path);
    if (summary.events != events) std::abort();  // two reads of one file agree
  } catch (const std::runtime_error&) {
  }
  return 0;
}
