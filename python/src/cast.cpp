/// rayproof.Mesh: ray casting (closest, any, all) on a triangle mesh given as numpy arrays, through
/// the public API rayproof::MeshCaster (include/rayproof/mesh_caster.h) with the float, robust or
/// certified method.
#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <variant>

#include "bindings.h"
#include "rayproof/mesh_caster.h"

namespace rayproof::python {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <class M>
struct Lazy {
  std::once_flag once;
  std::unique_ptr<MeshCaster<M>> caster;
};

class PyMesh {
 public:
  PyMesh(py::handle vertices, py::handle indices) {
    const py::array v = checked_array(vertices, "vertices", 3, false, DtypeRule::real);
    const py::array ix = checked_array(indices, "indices", 3, false, DtypeRule::integer);
    const auto vd = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
    const auto id = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(ix);
    if (!vd || !id) throw py::error_already_set();
    const std::size_t nv = static_cast<std::size_t>(vd.shape(0)), nt = static_cast<std::size_t>(id.shape(0));
    // A private packed copy: MeshCaster reads packed doubles in place, and the caller's array may change.
    vertices_.assign(vd.data(), vd.data() + 3 * nv);
    indices_.resize(3 * nt);
    const std::int64_t* ip = id.data();  // uint64 indices >= 2^63 wrap to negative here: caught below
    for (std::size_t i = 0; i < nt; ++i)
      for (std::size_t k = 0; k < 3; ++k) {
        const std::int64_t x = ip[3 * i + k];
        if (x < 0 || static_cast<std::uint64_t>(x) >= nv)
          throw py::value_error(fmt::format("indices: row {} has vertex index {} outside [0, {})", i, x, nv));
        indices_[3 * i + k] = static_cast<std::uint32_t>(x);
      }
    (void)caster<cast::Robust>();  // builds the default method's BVH now: bad input is reported here
  }

  [[nodiscard]] std::size_t triangles() const { return indices_.size() / 3; }
  [[nodiscard]] std::size_t vertices() const { return vertices_.size() / 3; }

  py::dict closest(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax,
                   int threads) {
    const auto rays = rays_of(origins, directions);
    const std::size_t n = rays.size();
    std::vector<MeshHit> hits(n);
    const TRange range{tmin, tmax};
    dispatch(method, [&](const auto& c) {
      py::gil_scoped_release unlocked;
      c.closest(rays, {&range, 1}, hits, threads);
    });
    return hit_arrays(hits);
  }

  py::array_t<bool> any(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax,
                        int threads) {
    const auto rays = rays_of(origins, directions);
    const std::size_t n = rays.size();
    std::vector<std::uint8_t> hit(n);
    const TRange range{tmin, tmax};
    dispatch(method, [&](const auto& c) {
      py::gil_scoped_release unlocked;
      c.any(rays, {&range, 1}, hit, threads);
    });
    py::array_t<bool> out(static_cast<py::ssize_t>(n));
    for (std::size_t i = 0; i < n; ++i) out.mutable_data()[i] = hit[i] != 0;
    return out;
  }

  py::dict all(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax) {
    const auto rays = rays_of(origins, directions);
    const std::size_t n = rays.size();
    std::vector<std::int64_t> offsets(n + 1, 0);
    std::vector<MeshHit> flat;
    const TRange range{tmin, tmax};
    dispatch(method, [&](const auto& c) {
      py::gil_scoped_release unlocked;
      for (std::size_t i = 0; i < n; ++i) {
        const auto hits = c.all(rays[i], range);
        flat.insert(flat.end(), hits.begin(), hits.end());
        offsets[i + 1] = static_cast<std::int64_t>(flat.size());
      }
    });
    py::dict out = hit_arrays(flat);
    out.attr("pop")("hit");  // every listed crossing is a hit
    py::array_t<std::int64_t> ray(static_cast<py::ssize_t>(flat.size()));
    for (std::size_t i = 0, k = 0; i < n; ++i)
      for (; k < static_cast<std::size_t>(offsets[i + 1]); ++k) ray.mutable_data()[k] = static_cast<std::int64_t>(i);
    out["offsets"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(n + 1), offsets.data());
    out["ray"] = ray;
    return out;
  }

 private:
  /// The per-hit arrays of `hits`: hit, prim (-1 for a miss), t, b1, b2, classes, codes.
  static py::dict hit_arrays(std::span<const MeshHit> hits) {
    const auto n = static_cast<py::ssize_t>(hits.size());
    py::array_t<std::uint8_t> codes(n);
    py::array_t<double> t(n), b1(n), b2(n);
    py::array_t<std::int64_t> prim(n);
    py::array_t<bool> hit(n);
    for (std::size_t i = 0; i < hits.size(); ++i) {
      const MeshHit& h = hits[i];
      codes.mutable_data()[i] = static_cast<std::uint8_t>(h.contact);
      hit.mutable_data()[i] = h.hit();
      prim.mutable_data()[i] = h.hit() ? static_cast<std::int64_t>(h.triangle) : -1;
      t.mutable_data()[i] = h.t;
      b1.mutable_data()[i] = h.b1;
      b2.mutable_data()[i] = h.b2;
    }
    py::dict out;
    out["hit"] = hit;
    out["prim"] = prim;
    out["t"] = t;
    out["b1"] = b1;
    out["b2"] = b2;
    out["classes"] = class_names(codes);
    out["codes"] = codes;
    return out;
  }
  /// The caster of method M, built on first use (once, even with concurrent callers; the GIL is
  /// released while the BVH is built). MeshInputError becomes ValueError.
  template <class M>
  const MeshCaster<M>& caster() {
    auto& lazy = std::get<Lazy<M>>(casters_);
    std::string error;
    {
      py::gil_scoped_release unlocked;
      std::call_once(lazy.once, [&] {
        try {
          lazy.caster = std::make_unique<MeshCaster<M>>(VertexArray(vertices_.data(), vertices()),
                                                        IndexArray{indices_.data(), triangles()});
        } catch (const MeshInputError& e) {
          error = e.what();
        }
      });
    }
    if (!error.empty()) throw py::value_error(fmt::format("mesh: {}", error));
    if (!lazy.caster) throw py::value_error("mesh: the arrays were rejected (see the first error)");
    return *lazy.caster;
  }

  template <class F>
  void dispatch(const std::string& method, F&& f) {
    if (method == "float") return f(caster<cast::Float>());
    if (method == "robust") return f(caster<cast::Robust>());
    if (method == "certified") return f(caster<cast::Certified>());
    throw py::value_error(fmt::format("method: '{}' is not a mesh casting method (float, robust, certified)", method));
  }

  static std::vector<Ray<double>> rays_of(py::handle origins, py::handle directions) {
    const Rows o = rows_of(origins, "origins", 3, true);
    const Rows d = rows_of(directions, "directions", 3, true);
    const std::size_t n = common_rows({{"origins", &o}, {"directions", &d}});
    std::vector<Ray<double>> rays(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double* a = o.row(i);
      const double* b = d.row(i);
      rays[i].o = {a[0], a[1], a[2]};
      rays[i].d = {b[0], b[1], b[2]};
    }
    return rays;
  }

  std::vector<double> vertices_;
  std::vector<std::uint32_t> indices_;
  std::tuple<Lazy<cast::Float>, Lazy<cast::Robust>, Lazy<cast::Certified>> casters_;
};

}  // namespace

void bind_cast(py::module_& m) {
  using namespace pybind11::literals;
  py::class_<PyMesh>(m, "Mesh", R"doc(A triangle mesh in a BVH, for ray casting (rayproof::MeshCaster).

Mesh(vertices, indices): vertices (n, 3) float32 or float64 (integers are converted), indices (m, 3) of an integer dtype
(uint32, int32, int64, ...), each in [0, n); the vertices the triangles use must be finite. The
arrays are copied. Zero triangles is an empty mesh (every ray misses).

Queries take origins and directions ((r, 3), or (3,) broadcast) and a method:
  'float'      Möller–Trumbore on the float-rounded ray and vertices: fast, can leak between
               triangles that share an edge or vertex;
  'robust'     watertight test with conservative traversal: no leaks (the default);
  'certified'  exact classes, t within one ulp of the exact t (no barycentrics: NaN).
A ray with a NaN or infinite component or a zero direction has no crossing (closest gives class
'invalid'). A crossing counts when tmin <= t <= tmax. Each method's BVH is built on its first use.)doc")
      .def(py::init<py::handle, py::handle>(), "vertices"_a, "indices"_a)
      .def_property_readonly("num_triangles", &PyMesh::triangles)
      .def_property_readonly("num_vertices", &PyMesh::vertices)
      .def("closest", &PyMesh::closest, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0,
           "tmax"_a = kInf, "threads"_a = 0,
           "Closest crossing per ray (ties: lower triangle number). Returns a dict of arrays: 'hit' (bool), "
           "'prim' (int64 triangle number, -1 for none), 't' (NaN for none), 'b1', 'b2' (barycentrics of the "
           "triangle's 2nd and 3rd vertex; NaN for none and for certified), 'classes', 'codes'. "
           "threads: 0 = every hardware thread. The GIL is released.")
      .def("any", &PyMesh::any, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0, "tmax"_a = kInf,
           "threads"_a = 0, "Whether each ray crosses the mesh (occlusion): a bool array. The GIL is released.")
      .def("all", &PyMesh::all, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0, "tmax"_a = kInf,
           "Every crossing of every ray, sorted by t then triangle within a ray: a dict of flat arrays 'ray', "
           "'prim', 't', 'b1', 'b2', 'classes', 'codes', and 'offsets' (r + 1: ray i's crossings are "
           "offsets[i]:offsets[i+1]). The GIL is released.");
}

}  // namespace rayproof::python
