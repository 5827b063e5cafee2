#pragma once
// An in-process bus for tests: LCM over memq:// (delivers to the publishing
// instance only) and shared-memory segments named for this test process.
#include <unistd.h>

#include <string>

#include "edsp/transport/bus.h"

namespace edsp::test_support {

inline TransportConfig MemqConfig(const std::string& name) {
  TransportConfig config;
  config.lcm_url = "memq://";
  config.shm_prefix = "edsp." + name + "." + std::to_string(::getpid());
  return config;
}

}  // namespace edsp::test_support
