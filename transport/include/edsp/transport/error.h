#pragma once
// Transport errors raised at set-up time (bad URL, incompatible segment).
// The publish/take paths report through return values instead.

#include <stdexcept>

namespace edsp {

class TransportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace edsp
