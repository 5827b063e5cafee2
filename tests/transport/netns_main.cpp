// main() for multi-process tests that use LCM multicast: every test runs in a
// private network namespace, so no packet leaves the machine.
#include <cstdio>

#include <gtest/gtest.h>

#include "edsp/transport/error.h"
#include "edsp/transport/private_network.h"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  try {
    edsp::EnterPrivateNetworkNamespace();
  } catch (const edsp::TransportError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return RUN_ALL_TESTS();
}
