/// rayproof.classify: batch classification of numpy rays against primitives with any method.
#include <fmt/core.h>

#include <cmath>
#include <limits>

#include "bindings.h"

namespace rayproof::python {

namespace {

/// Runs `meth` on n cases in chunks with the GIL released (Ctrl-C checked between chunks; exact takes
/// about 30 us a case): fill(i, case) writes case i's kind and fields, take(i, result) keeps its
/// answer. Float methods see the fields rounded to float, as Method::run does.
template <class Fill, class Take>
void classify_chunked(const Method& meth, std::size_t n, Fill fill, Take take) {
  py::gil_scoped_release unlocked;
  constexpr std::size_t kChunk = 4096;
  std::vector<io::Case> cases;
  std::vector<io::CaseResult> results;
  for (std::size_t start = 0; start < n; start += kChunk) {
    if (start > 0) {
      py::gil_scoped_acquire locked;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
    const std::size_t m = std::min(kChunk, n - start);
    cases.assign(m, io::Case{});
    results.assign(m, io::CaseResult{});
    for (std::size_t j = 0; j < m; ++j) {
      fill(start + j, cases[j]);
      if (meth.precision == Precision::float32) cases[j] = io::round_to_float(cases[j]);
    }
    meth.classify_many(cases, results);
    for (std::size_t j = 0; j < m; ++j) take(start + j, results[j]);
  }
}

py::dict classify(const std::string& kind_name, py::handle origins, py::handle directions, py::handle prims,
                  const std::string& method_name) {
  const io::Kind kind = kind_named(kind_name);
  if (kind == io::Kind::tritri)  // two triangles, no ray: not this function's (origins, directions, prims)
    throw py::value_error("kind: 'tritri' cases have no ray; classify triangle pairs with "
                          "rayproof.classify_pairs(a, b, method), check a pair kernel with rayproof.check(f, kind='tritri')");
  const Method& meth = method_named(method_name);
  if (!meth.supports(kind))
    throw py::value_error(fmt::format("method: '{}' does not answer {} cases", meth.name, kind_name));
  const std::size_t width = static_cast<std::size_t>(io::field_count(kind) - 6);
  const Rows o = rows_of(origins, "origins", 3, true);
  const Rows d = rows_of(directions, "directions", 3, true);
  const Rows p = rows_of(prims, "prims", width, true);
  const std::size_t n = common_rows({{"origins", &o}, {"directions", &d}, {"prims", &p}});

  py::array_t<std::uint8_t> codes(static_cast<py::ssize_t>(n));
  py::array_t<double> t(static_cast<py::ssize_t>(n)), t2(static_cast<py::ssize_t>(n));
  std::uint8_t* code_out = codes.mutable_data();
  double* t_out = t.mutable_data();
  double* t2_out = t2.mutable_data();
  classify_chunked(
      meth, n,
      [&](std::size_t i, io::Case& c) {
        c.kind = kind;
        std::copy_n(o.row(i), 3, c.v.begin());
        std::copy_n(d.row(i), 3, c.v.begin() + 3);
        std::copy_n(p.row(i), width, c.v.begin() + 6);
      },
      [&](std::size_t i, const io::CaseResult& r) {
        code_out[i] = static_cast<std::uint8_t>(r.contact);
        t_out[i] = r.t.value_or(std::numeric_limits<double>::quiet_NaN());
        t2_out[i] = r.t2.value_or(std::numeric_limits<double>::quiet_NaN());
      });
  py::dict out;
  out["classes"] = class_names(codes);
  out["codes"] = codes;
  out["t"] = t;
  out["t2"] = t2;
  return out;
}

/// Triangles as rows of 9 numbers (p0 p1 p2): (n, 9), (n, 3, 3), or one triangle ((9,) or (3, 3))
/// broadcast to every row.
Rows triangle_rows(py::handle obj, const char* arg) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::type_error(fmt::format("{}: expected an array of triangles", arg));
  if (a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 3) a = a.attr("reshape")(a.shape(0), 9);
  else if (a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 3) a = a.attr("reshape")(9);
  else if (!((a.ndim() == 2 && a.shape(1) == 9) || (a.ndim() == 1 && a.shape(0) == 9)))
    throw py::value_error(fmt::format("{}: expected triangles of shape (n, 3, 3) or (n, 9), or one of shape (3, 3) "
                                      "or (9,); got {} dimension(s)", arg, a.ndim()));
  return rows_of(a, arg, 9, true);
}

py::dict classify_pairs(py::handle first, py::handle second, const std::string& method_name) {
  const Method& meth = method_named(method_name);
  if (!meth.supports(io::Kind::tritri))
    throw py::value_error(fmt::format("method: '{}' does not answer triangle pairs (kind tritri)", meth.name));
  const Rows a = triangle_rows(first, "a");
  const Rows b = triangle_rows(second, "b");
  const std::size_t n = common_rows({{"a", &a}, {"b", &b}});
  py::array_t<std::uint8_t> codes(static_cast<py::ssize_t>(n));
  std::uint8_t* code_out = codes.mutable_data();
  classify_chunked(
      meth, n,
      [&](std::size_t i, io::Case& c) {
        c.kind = io::Kind::tritri;
        std::copy_n(a.row(i), 9, c.v.begin());
        std::copy_n(b.row(i), 9, c.v.begin() + 9);
      },
      [&](std::size_t i, const io::CaseResult& r) { code_out[i] = static_cast<std::uint8_t>(r.contact); });
  py::dict out;
  out["classes"] = class_names(codes);
  out["codes"] = codes;
  return out;
}

}  // namespace

void bind_classify(py::module_& m) {
  using namespace pybind11::literals;
  m.def("classify", &classify, "kind"_a, "origins"_a, "directions"_a, "prims"_a, "method"_a = "certified",
        R"doc(Classify rays against primitives of one kind with a registered method.

kind: 'plane', 'sphere', 'ellipsoid', 'triangle', 'box' or 'disk'.
origins, directions: (n, 3) arrays, or (3,) broadcast to every row.
prims: (n, k) or (k,) broadcast; k = PRIM_WIDTH[kind], the fields of docs/cases.md after o and d
  (triangle: p0 p1 p2 = 9; sphere: center radius = 4; plane: point normal = 6; ellipsoid: center
  semi-axes = 6; box: lo hi = 6; disk: center normal radius = 7).
Every array may be float or integer; values are converted to float64. Float methods see the
inputs rounded to float, as everywhere in rayproof.
Returns a dict of numpy arrays of length n: 'classes' (class names, CLASS_NAMES), 'codes' (uint8
index into CLASS_NAMES), 't' and 't2' (float64, NaN where the class carries no value).
The GIL is released while the method runs.)doc");
  m.def("classify_pairs", &classify_pairs, "a"_a, "b"_a, "method"_a = "certified",
        R"doc(Classify triangle pairs (kind 'tritri', docs/tritri.md) with a registered method.

a, b: triangles, (n, 3, 3) or (n, 9) arrays (p0 p1 p2 per row), or one triangle ((3, 3) or (9,))
  broadcast to every row. Any float or integer dtype; values are converted to float64, and float
  methods see them rounded to float.
method: 'certified' (default) or 'exact' answer the class: 'disjoint', 'crossing', 'touching',
  'coplanar_overlap', 'coplanar_touching', or 'degenerate' / 'invalid'. The classic tests
  ('moller-float', 'moller-double', 'gd-float', 'gd-double') answer 'hit' (they meet) or 'miss'.
Returns a dict: 'classes' (numpy array of class names) and 'codes' (uint8 index into CLASS_NAMES).
The GIL is released while the method runs.)doc");
}

}  // namespace rayproof::python
