/// The Python module `rayproof`: rayproof's methods, exact verification and mesh ray casting on
/// numpy arrays (pybind11). See python/README.md for the API.
#include <fmt/core.h>

#include "bindings.h"
#include "registry/registry.h"

namespace rayproof::python {

// The tool's registry: the module answers with exactly the methods `rayproof methods` lists.
const MethodRegistry& registry() { return registry::all_methods(); }

const Method& method_named(const std::string& name) {
  if (const Method* m = registry().find(name)) return *m;
  throw py::value_error(fmt::format("method: unknown method '{}' (known: {})", name, registry().names()));
}

io::Kind kind_named(const std::string& name) {
  if (auto k = io::kind_from_string(name)) return *k;
  throw py::value_error(fmt::format("kind: unknown kind '{}' (known: plane, sphere, ellipsoid, triangle, box, disk, tritri)", name));
}

namespace {
std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += fmt::format("{}{}", i ? ", " : "", a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}
}  // namespace

py::array checked_array(py::handle obj, const char* arg, std::size_t width, bool allow_broadcast, DtypeRule rule) {
  if (obj.is_none()) throw py::type_error(fmt::format("{}: expected an array, got None", arg));
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw py::type_error(fmt::format("{}: not convertible to a numpy array ({})", arg, e.what()));
  }
  const char k = a.dtype().kind();
  const bool ok = rule == DtypeRule::real       ? (k == 'f' || k == 'i' || k == 'u')
                  : rule == DtypeRule::floating ? k == 'f'
                                                : (k == 'i' || k == 'u');
  if (!ok) {
    const char* want = rule == DtypeRule::real ? "real numbers (float or integer dtype)"
                       : rule == DtypeRule::floating ? "floats (float32 or float64)"
                                                     : "integers (e.g. uint32, int32, int64)";
    throw py::type_error(fmt::format("{}: expected an array of {}, got dtype {}", arg, want,
                                     py::str(a.dtype()).cast<std::string>()));
  }
  const bool two_d = a.ndim() == 2 && static_cast<std::size_t>(a.shape(1)) == width;
  const bool one_d = allow_broadcast && a.ndim() == 1 && static_cast<std::size_t>(a.shape(0)) == width;
  if (!two_d && !one_d)
    throw py::value_error(fmt::format("{}: expected shape (n, {}){}, got {}", arg, width,
                                      allow_broadcast ? fmt::format(" or ({},)", width) : std::string(),
                                      shape_text(a)));
  return a;
}

Rows rows_of(py::handle obj, const char* arg, std::size_t width, bool allow_broadcast) {
  py::array a = checked_array(obj, arg, width, allow_broadcast, DtypeRule::real);
  Rows r;
  r.width = width;
  r.broadcast = a.ndim() == 1;
  r.rows = r.broadcast ? 0 : static_cast<std::size_t>(a.shape(0));
  r.data = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!r.data) throw py::error_already_set();
  return r;
}

std::size_t common_rows(const std::vector<std::pair<const char*, const Rows*>>& args) {
  const char* first = nullptr;
  std::size_t n = 0;
  for (const auto& [name, r] : args) {
    if (r->broadcast) continue;
    if (!first) {
      first = name, n = r->rows;
    } else if (r->rows != n) {
      throw py::value_error(fmt::format("{}: {} rows, but {} has {}", name, r->rows, first, n));
    }
  }
  return first ? n : 1;
}

py::object class_names(const py::array_t<std::uint8_t>& codes) {
  static const py::object table = [] {
    py::list names;
    for (auto s : kContactNames) names.append(py::str(std::string(s)));
    return py::module_::import("numpy").attr("array")(names);
  }();
  return table.attr("__getitem__")(codes);
}

}  // namespace rayproof::python

PYBIND11_MODULE(rayproof, m) {
  namespace py = pybind11;
  using namespace rayproof;
  using namespace rayproof::python;
  m.doc() = "rayproof: ray intersection kernels verified against exact arithmetic (CGAL, GMP, MPFR)";
  m.attr("__version__") = "0.1.0";
  {
    py::tuple names(kContactNames.size());
    for (std::size_t i = 0; i < kContactNames.size(); ++i) names[i] = py::str(std::string(kContactNames[i]));
    m.attr("CLASS_NAMES") = names;
  }
  {
    py::dict widths;
    for (io::Kind k : io::kAllKinds) widths[py::str(std::string(io::to_string(k)))] = io::field_count(k) - 6;
    m.attr("PRIM_WIDTH") = widths;
  }
  m.def(
      "methods",
      [] {
        py::list out;
        for (const auto& meth : python::registry().all()) {
          py::dict d;
          d["name"] = meth.name;
          d["summary"] = meth.summary;
          d["precision"] = meth.precision == Precision::float32 ? "float" : "double";
          py::list kinds;
          for (io::Kind k : meth.kinds) kinds.append(std::string(io::to_string(k)));
          d["kinds"] = kinds;
          out.append(d);
        }
        return out;
      },
      "Every registered method: a list of dicts with name, summary, precision ('float' or 'double') and kinds.");
  bind_classify(m);
  bind_cast(m);
  bind_check(m);
  bind_load_mesh(m);
  bind_check_caster(m);
  bind_check_contains(m);
  bind_check_crossings(m);
}
