// The module _edsp: its parts (bindings.h), under one name.
#include "bindings.h"

PYBIND11_MODULE(_edsp, m) {
  m.doc() = "edsp's C++ core: kinematics, logs and recordings, the gap diagnosis, the motion service's client";
  edsp::python::BindErrors(m);
  edsp::python::BindKinematics(m);
  edsp::python::BindMotion(m);
  edsp::python::BindData(m);
  edsp::python::BindGap(m);
}
