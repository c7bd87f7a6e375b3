#pragma once
/// Shared pieces of the Python module: the method registry, numpy argument checks with errors that
/// name the argument, and the per-part binding functions.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/vec3.h"

namespace rayproof::python {

namespace py = pybind11;

/// Every registered method: fast, exact, robust, certified (as the command-line tool has them).
[[nodiscard]] const MethodRegistry& registry();

/// The method called `name`; ValueError naming the known ones when there is none.
[[nodiscard]] const Method& method_named(const std::string& name);

/// The kind called `name`; ValueError naming the kinds when there is none.
[[nodiscard]] io::Kind kind_named(const std::string& name);

/// A 2-D array of `width` columns (`rows` rows), or a 1-D array of `width` values broadcast to
/// every row, as C-contiguous float64.
struct Rows {
  py::array_t<double, py::array::c_style | py::array::forcecast> data;
  bool broadcast = false;
  std::size_t rows = 0;  ///< 0 when broadcast
  [[nodiscard]] const double* row(std::size_t i) const { return data.data() + (broadcast ? 0 : i * width); }
  std::size_t width = 0;
};

enum class DtypeRule { real, floating, integer };

/// Checks `obj` (an array or anything numpy.asarray takes) for dtype and shape: TypeError for a
/// dtype outside the rule, ValueError for a shape other than (n, width) or, with broadcast
/// allowed, (width,). Both messages name `arg`.
[[nodiscard]] py::array checked_array(py::handle obj, const char* arg, std::size_t width, bool allow_broadcast,
                                      DtypeRule rule);
[[nodiscard]] Rows rows_of(py::handle obj, const char* arg, std::size_t width, bool allow_broadcast);

/// The common row count of several Rows (the 2-D ones must agree; all broadcast: 1).
/// ValueError naming the two arguments that disagree.
[[nodiscard]] std::size_t common_rows(const std::vector<std::pair<const char*, const Rows*>>& args);

/// numpy array of class names for an array of Contact codes.
[[nodiscard]] py::object class_names(const py::array_t<std::uint8_t>& codes);

void bind_classify(py::module_& m);
void bind_cast(py::module_& m);
void bind_check(py::module_& m);
void bind_load_mesh(py::module_& m);
/// A mesh's vertex and triangle arrays, checked (dtype, shape, indices in range: ValueError naming
/// the row) and copied (check_caster.cpp; the judges' bindings use it).
struct CheckedMesh {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};
[[nodiscard]] CheckedMesh checked_mesh(py::handle vertices, py::handle triangles);
/// Whether a Python exception is KeyboardInterrupt or SystemExit (to be raised again, not counted).
[[nodiscard]] bool is_interrupt(const py::error_already_set& e);

void bind_check_caster(py::module_& m);
void bind_check_contains(py::module_& m);
void bind_check_crossings(py::module_& m);

}  // namespace rayproof::python
