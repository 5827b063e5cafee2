#pragma once
// _edsp, the C++ side of the Python package edsp (python/edsp/__init__.py
// is the API users see; docs/python.md), one part per file:
//   kinematics_binding.cpp  the kinematics on numpy arrays, GIL released
//   motion_binding.cpp      the motion service's client on edsp's Bus
//   data_binding.cpp        LCM logs and live recordings as numpy columns
//   gap_binding.cpp         the gap diagnosis (edsp-gap's JSON)
//   errors.cpp              edsp's exceptions, one class per reply family
// and what they share: arguments checked and named.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "edsp/kinematics/passive_rotation.h"

namespace edsp::python {

namespace py = pybind11;

using Rows = py::array_t<double, py::array::c_style | py::array::forcecast>;

// `value` as an (N, 6) float64 array, or a TypeError/ValueError naming
// `argument`, the row and the column of a non-finite value.
Rows SixColumns(const py::handle& value, const char* argument);

// "none", "unsigned", "signed", "asin", or a ValueError naming it.
PrMode ModeOf(const std::string& text);

void BindErrors(py::module_& m);
void BindKinematics(py::module_& m);
void BindMotion(py::module_& m);
void BindData(py::module_& m);
void BindGap(py::module_& m);

}  // namespace edsp::python
