#include <cmath>
#include <string>

#include <fmt/format.h>

#include "bindings.h"

namespace edsp::python {

Rows SixColumns(const py::handle& value, const char* argument) {
  if (!py::isinstance<py::array>(value) && !py::isinstance<py::sequence>(value)) {
    throw py::type_error(fmt::format("{}: want an array of shape (N, 6) or (6,), got {}", argument,
                                     std::string(py::str(value.get_type().attr("__name__")))));
  }
  const py::array raw = py::array::ensure(value);
  if (!raw) throw py::type_error(fmt::format("{}: not convertible to a float64 array", argument));
  if (raw.dtype().kind() != 'f' && raw.dtype().kind() != 'i' && raw.dtype().kind() != 'u') {
    throw py::type_error(fmt::format("{}: want numbers, got dtype {}", argument, std::string(py::str(raw.dtype()))));
  }
  Rows rows = Rows::ensure(raw);
  if (rows.ndim() == 1 && rows.shape(0) == 6) rows = rows.reshape({py::ssize_t{1}, py::ssize_t{6}});
  if (rows.ndim() != 2 || rows.shape(1) != 6) {
    std::string shape;
    for (py::ssize_t k = 0; k < rows.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(rows.shape(k));
    throw py::value_error(fmt::format("{}: want shape (N, 6) or (6,), got ({})", argument, shape));
  }
  const double* data = rows.data();
  for (py::ssize_t i = 0; i < rows.shape(0) * 6; ++i) {
    if (!std::isfinite(data[i])) {
      throw py::value_error(
          fmt::format("{}: row {} column {} is {} (every value must be finite)", argument, i / 6, i % 6, data[i]));
    }
  }
  return rows;
}

PrMode ModeOf(const std::string& text) {
  PrMode mode;
  if (!ParsePrMode(text.c_str(), &mode)) {
    throw py::value_error("pr_mode " + text + ": use none, unsigned, signed or asin");
  }
  return mode;
}

}  // namespace edsp::python
