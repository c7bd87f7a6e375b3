/// rayproof.Mesh: ray casting (closest, any, all) on a triangle mesh given as numpy arrays, through
/// the scene's four-wide BVH (src/scene/accel.h) with a compiled or registry method.
#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <memory>

#include "bindings.h"
#include "scene/accel.h"

namespace rayproof::python {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaNd = std::numeric_limits<double>::quiet_NaN();

class PyMesh {
 public:
  PyMesh(py::handle vertices, py::handle indices) {
    const py::array v = checked_array(vertices, "vertices", 3, false, DtypeRule::floating);
    const py::array ix = checked_array(indices, "indices", 3, false, DtypeRule::integer);
    const auto vd = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
    const auto id = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(ix);
    if (!vd || !id) throw py::error_already_set();
    const std::size_t nv = static_cast<std::size_t>(vd.shape(0)), nt = static_cast<std::size_t>(id.shape(0));
    if (nt == 0) throw py::value_error("indices: the mesh has no triangles (shape (0, 3))");
    if (nv >= std::numeric_limits<std::uint32_t>::max())
      throw py::value_error(fmt::format("vertices: {} vertices, at most 4294967294 are supported", nv));
    // uint64 indices above 2^63 wrap to negative int64 in the cast above and are caught as negative.
    scene_ = std::make_unique<scene::Scene>();
    auto& mesh = scene_->mesh;
    mesh.vertices.resize(nv);
    const double* vp = vd.data();
    for (std::size_t i = 0; i < nv; ++i) {
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(vp[3 * i + k]))
          throw py::value_error(fmt::format("vertices: row {} is not finite ({}, {}, {})", i, vp[3 * i],
                                            vp[3 * i + 1], vp[3 * i + 2]));
      mesh.vertices[i] = {vp[3 * i], vp[3 * i + 1], vp[3 * i + 2]};
    }
    mesh.triangles.resize(nt);
    const std::int64_t* ip = id.data();
    for (std::size_t i = 0; i < nt; ++i)
      for (int k = 0; k < 3; ++k) {
        const std::int64_t x = ip[3 * i + k];
        if (x < 0 || static_cast<std::uint64_t>(x) >= nv)
          throw py::value_error(fmt::format("indices: row {} has vertex index {} outside [0, {})", i, x, nv));
        mesh.triangles[i][k] = static_cast<std::uint32_t>(x);
      }
    py::gil_scoped_release unlocked;
    accel_ = std::make_unique<scene::Accel>(*scene_);
  }

  [[nodiscard]] std::size_t triangles() const { return scene_->mesh.triangles.size(); }
  [[nodiscard]] std::size_t vertices() const { return scene_->mesh.vertices.size(); }

  py::dict closest(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax,
                   int threads) const {
    const auto rays = rays_of(origins, directions);
    const scene::SceneMethod sm = scene_method(method);
    const std::size_t n = rays.size();
    py::array_t<std::uint8_t> codes(static_cast<py::ssize_t>(n));
    py::array_t<double> t(static_cast<py::ssize_t>(n));
    py::array_t<std::int64_t> prim(static_cast<py::ssize_t>(n));
    auto* co = codes.mutable_data();
    auto* to = t.mutable_data();
    auto* po = prim.mutable_data();
    {
      py::gil_scoped_release unlocked;
      std::vector<scene::PrimHit> hits(n);
      accel_->closest_batch(rays, hits, sm, threads, {tmin, tmax});
      for (std::size_t i = 0; i < n; ++i) {
        const bool valid = rays[i].valid();
        const bool none = !valid || hits[i].prim == scene::PrimHit::kNoPrim;
        co[i] = static_cast<std::uint8_t>(valid ? hits[i].contact : Contact::invalid);
        to[i] = none ? kNaNd : hits[i].t;
        po[i] = none ? -1 : static_cast<std::int64_t>(hits[i].prim);
      }
    }
    py::dict out;
    out["hit"] = py::array(prim.attr("__ge__")(0));
    out["prim"] = prim;
    out["t"] = t;
    out["classes"] = class_names(codes);
    out["codes"] = codes;
    return out;
  }

  py::array_t<bool> any(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax,
                        int threads) const {
    const auto rays = rays_of(origins, directions);
    const scene::SceneMethod sm = scene_method(method);
    const std::size_t n = rays.size();
    py::array_t<bool> out(static_cast<py::ssize_t>(n));
    bool* o = out.mutable_data();
    {
      py::gil_scoped_release unlocked;
      std::vector<std::uint8_t> hit(n);
      accel_->any_batch(rays, hit, sm, threads, {tmin, tmax});
      for (std::size_t i = 0; i < n; ++i) o[i] = rays[i].valid() && hit[i];
    }
    return out;
  }

  py::dict all(py::handle origins, py::handle directions, const std::string& method, double tmin, double tmax) const {
    const auto rays = rays_of(origins, directions);
    const scene::SceneMethod sm = scene_method(method);
    const std::size_t n = rays.size();
    std::vector<std::int64_t> offsets(n + 1, 0);
    std::vector<scene::PrimHit> flat;
    {
      py::gil_scoped_release unlocked;
      for (std::size_t i = 0; i < n; ++i) {
        if (rays[i].valid()) {
          auto hits = accel_->all(rays[i], sm, {tmin, tmax});
          flat.insert(flat.end(), hits.begin(), hits.end());
        }
        offsets[i + 1] = static_cast<std::int64_t>(flat.size());
      }
    }
    const auto m = static_cast<py::ssize_t>(flat.size());
    py::array_t<std::int64_t> ray(m), prim(m);
    py::array_t<double> t(m);
    py::array_t<std::uint8_t> codes(m);
    for (std::size_t i = 0, k = 0; i < n; ++i)
      for (; k < static_cast<std::size_t>(offsets[i + 1]); ++k) {
        ray.mutable_data()[k] = static_cast<std::int64_t>(i);
        prim.mutable_data()[k] = flat[k].prim;
        t.mutable_data()[k] = flat[k].t;
        codes.mutable_data()[k] = static_cast<std::uint8_t>(flat[k].contact);
      }
    py::dict out;
    out["offsets"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(n + 1), offsets.data());
    out["ray"] = ray;
    out["prim"] = prim;
    out["t"] = t;
    out["classes"] = class_names(codes);
    out["codes"] = codes;
    return out;
  }

 private:
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
  static scene::SceneMethod scene_method(const std::string& name) {
    try {
      return scene::find_scene_method(name, registry());
    } catch (const scene::SceneError& e) {
      throw py::value_error(fmt::format("method: {}", e.what()));
    }
  }

  std::unique_ptr<scene::Scene> scene_;  // the Accel refers to it: kept at a fixed address
  std::unique_ptr<scene::Accel> accel_;
};

}  // namespace

void bind_cast(py::module_& m) {
  using namespace pybind11::literals;
  py::class_<PyMesh>(m, "Mesh", R"doc(A triangle mesh in a four-wide BVH, for ray casting.

Mesh(vertices, indices): vertices (n, 3) float32 or float64 (finite), indices (m, 3) of an integer
dtype (uint32, int32, int64, ...), each in [0, n). The arrays are copied.

Queries take origins and directions ((r, 3), or (3,) broadcast) and a method: 'float', 'double',
'robust' (watertight, conservative traversal: no leaks between shared edges), 'certified' (exact
classes, t within one ulp), or another compiled or registered method. A ray with a NaN or
infinite component or a zero direction is invalid: closest gives class 'invalid', any gives False,
all gives no crossing. Only crossings with tmin <= t <= tmax count.)doc")
      .def(py::init<py::handle, py::handle>(), "vertices"_a, "indices"_a)
      .def_property_readonly("num_triangles", &PyMesh::triangles)
      .def_property_readonly("num_vertices", &PyMesh::vertices)
      .def("closest", &PyMesh::closest, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0,
           "tmax"_a = kInf, "threads"_a = 0,
           "Closest crossing per ray (ties: lower triangle number). Returns a dict of arrays: 'hit' (bool), "
           "'prim' (int64 triangle number, -1 for none), 't' (NaN for none), 'classes', 'codes'. "
           "threads: 0 = every hardware thread. The GIL is released.")
      .def("any", &PyMesh::any, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0, "tmax"_a = kInf,
           "threads"_a = 0, "Whether each ray crosses the mesh (occlusion): a bool array. The GIL is released.")
      .def("all", &PyMesh::all, "origins"_a, "directions"_a, "method"_a = "robust", "tmin"_a = 0.0, "tmax"_a = kInf,
           "Every crossing of every ray, sorted by t then triangle within a ray: a dict of flat arrays 'ray', "
           "'prim', 't', 'classes', 'codes', and 'offsets' (r + 1: ray i's crossings are "
           "offsets[i]:offsets[i+1]). The GIL is released.");
}

}  // namespace rayproof::python
