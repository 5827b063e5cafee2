#include "edsp/node/request_client.h"

#include <limits>
#include <random>

namespace edsp {

std::int64_t RequestClient::NewRequestId() {
  std::random_device device;
  std::uniform_int_distribution<std::int64_t> id(1, std::numeric_limits<std::int64_t>::max());
  return id(device);
}

}  // namespace edsp
