#pragma once
// What a request to a running group can end in, as C++ exceptions the
// module turns into Python's (errors.cpp): one class per family of reply
// code or wait outcome, each carrying the code's name.

#include <stdexcept>
#include <string>

namespace edsp::python {

enum class ErrorFamily { kRefused, kTimeout, kHalted, kFault };

class RequestError : public std::runtime_error {
 public:
  RequestError(ErrorFamily family, std::string code, const std::string& message)
      : std::runtime_error(message), family_(family), code_(std::move(code)) {}
  ErrorFamily family() const { return family_; }
  const std::string& code() const { return code_; }  // "not_now", "timeout", "halted", ...

 private:
  ErrorFamily family_;
  std::string code_;
};

}  // namespace edsp::python
