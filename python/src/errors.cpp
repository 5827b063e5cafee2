// edsp's Python exceptions, made here so that the module raises them
// itself: EdspError and one subclass per family of reply code or wait
// outcome (RefusedError, TimeoutError, HaltedError, FaultError), each with
// `.code`, the reply code's or the outcome's name (reply_codes.h). edsp's
// TimeoutError is also Python's, as `except TimeoutError` expects.
#include "errors.h"

#include "bindings.h"
#include "edsp/reply_codes.h"

namespace edsp::python {

namespace {

py::object NewClass(py::module_& m, const char* name, const py::handle& bases, const char* doc) {
  const std::string qualified = std::string("edsp.") + name;
  py::object cls =
      py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr));
  if (!cls) throw py::error_already_set();
  m.attr(name) = cls;
  return cls;
}

// Made once, with the module; the interpreter keeps the module alive.
struct Classes {
  py::object refused, timeout, halted, fault;
};
Classes* classes = nullptr;

}  // namespace

void BindErrors(py::module_& m) {
  py::object base =
      NewClass(m, "EdspError", PyExc_Exception, "Anything edsp refuses or cannot do; the message says why.");
  classes = new Classes{
      NewClass(m, "RefusedError", base,
               "The node refused the request (its reason is the message; .code names why: invalid, not_now, "
               "out_of_limits, other_session, stale)."),
      NewClass(m, "TimeoutError", py::make_tuple(base, py::handle(PyExc_TimeoutError)),
               "No reply, or not on target, within the timeout."),
      NewClass(m, "HaltedError", base, "The motion ended in a halt or a stop requested by someone else."),
      NewClass(m, "FaultError", base,
               "The actuator bridge stopped following while waiting, or a node failed to act (re-arm it)."),
  };
  py::dict codes;
  for (const ReplyCodeRow& row : kReplyCodes) codes[py::str(std::string(row.name))] = static_cast<int>(row.code);
  m.attr("REPLY_CODES") = codes;
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const RequestError& e) {
      const py::object* cls = &classes->refused;
      switch (e.family()) {
        case ErrorFamily::kRefused: cls = &classes->refused; break;
        case ErrorFamily::kTimeout: cls = &classes->timeout; break;
        case ErrorFamily::kHalted: cls = &classes->halted; break;
        case ErrorFamily::kFault: cls = &classes->fault; break;
      }
      py::object error = (*cls)(e.what());
      error.attr("code") = e.code();
      PyErr_SetObject(cls->ptr(), error.ptr());
    }
  });
}

}  // namespace edsp::python
