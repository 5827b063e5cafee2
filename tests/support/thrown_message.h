#pragma once
// What a call throws, for the tests that check an error names what is wrong
// (the file, key, value).

#include <string>
#include <utility>

namespace edsp::test_support {

// e.what() of the `Error` that `call` throws; `none` when it throws nothing.
template <typename Error, typename Call>
std::string ThrownMessage(Call&& call, std::string none = "") {
  try {
    std::forward<Call>(call)();
  } catch (const Error& e) {
    return e.what();
  }
  return none;
}

}  // namespace edsp::test_support
