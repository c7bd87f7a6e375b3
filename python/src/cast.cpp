/// rayproof.Mesh: ray casting (closest, any, all) on a triangle mesh given as numpy arrays, through
/// the public API rayproof::MeshCaster (include/rayproof/scene/mesh_caster.h) with the float, robust or
/// certified method.
#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <variant>

#include "bindings.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/distance.h"
#include "rayproof/scene/intersections.h"
#include "rayproof/scene/mesh_caster.h"

namespace rayproof::python {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <class M>
struct Lazy {
  std::once_flag once;
  std::unique_ptr<MeshCaster<M>> caster;
};

/// A ExactMesh for one rule, built on first use.
struct LazyClosed {
  std::once_flag once;
  std::unique_ptr<ExactMesh> mesh;
  std::string error;
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

  /// contains(): one uint8 code per point (Side: 0 outside, 1 inside, 2 surface, 3 invalid). float64
  /// C-contiguous (n, 3) points are read in place (other dtypes and layouts are converted once).
  py::array_t<std::uint8_t> contains(py::handle points, const std::string& rule, int threads) {
    const Rows p = rows_of(points, "points", 3, true);
    const std::size_t n = p.broadcast ? 1 : p.rows;
    const ExactMesh& cm = closed(rule);
    py::array_t<std::uint8_t> out(static_cast<py::ssize_t>(n));
    const double* xyz = p.data.data();
    std::uint8_t* o = out.mutable_data();
    {
      py::gil_scoped_release unlocked;
      cm.contains(xyz, n, 3 * sizeof(double), o, threads);
    }
    return out;
  }

  /// distance() / signed_distance() / closest_points(): ExactMesh::closest_points over the points
  /// (float64 C-contiguous (n, 3) read in place), the GIL released (docs/distance.md).
  std::vector<ClosestPoint> nearest(py::handle points, bool with_side, int threads) {
    const Rows p = rows_of(points, "points", 3, true);
    const std::size_t n = p.broadcast ? 1 : p.rows;
    const ExactMesh& cm = closed("automatic");
    std::vector<ClosestPoint> r(n);
    const double* xyz = p.data.data();
    {
      py::gil_scoped_release unlocked;
      cm.closest_points(xyz, n, 3 * sizeof(double), r.data(), with_side, threads);
    }
    return r;
  }
  py::array_t<double> distance(py::handle points, int threads) {
    const std::vector<ClosestPoint> r = nearest(points, false, threads);
    py::array_t<double> out(static_cast<py::ssize_t>(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) out.mutable_data()[i] = r[i].distance;
    return out;
  }
  py::array_t<double> signed_distance(py::handle points, int threads) {
    const std::vector<ClosestPoint> r = nearest(points, true, threads);
    py::array_t<double> out(static_cast<py::ssize_t>(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) out.mutable_data()[i] = r[i].signed_distance();
    return out;
  }
  py::dict closest_points(py::handle points, bool side, int threads) {
    const std::vector<ClosestPoint> r = nearest(points, side, threads);
    const auto n = static_cast<py::ssize_t>(r.size());
    py::array_t<double> pts({n, py::ssize_t(3)}), bary({n, py::ssize_t(3)}), dist(n);
    py::array_t<std::int64_t> tri(n);
    py::array_t<std::uint8_t> sides(n);
    for (py::ssize_t i = 0; i < n; ++i) {
      const ClosestPoint& c = r[static_cast<std::size_t>(i)];
      double* q = pts.mutable_data(i, 0);
      q[0] = c.point.x, q[1] = c.point.y, q[2] = c.point.z;
      double* b = bary.mutable_data(i, 0);
      b[0] = c.barycentric[0], b[1] = c.barycentric[1], b[2] = c.barycentric[2];
      dist.mutable_data()[i] = c.distance;
      tri.mutable_data()[i] = c.triangle == ClosestPoint::kNoTriangle ? -1 : std::int64_t(c.triangle);
      sides.mutable_data()[i] = static_cast<std::uint8_t>(c.side);
    }
    py::dict out;
    out["points"] = pts, out["triangles"] = tri, out["barycentric"] = bary, out["distance"] = dist;
    if (side) out["side"] = sides;
    return out;
  }

  /// self_intersections() / intersecting_pairs(): rayproof/scene/intersections.h on the private
  /// copies, the GIL released; (k, 2) int64 pairs, sorted (docs/intersect.md).
  [[nodiscard]] MeshArrays arrays() const {
    return {VertexArray(vertices_.data(), vertices()), IndexArray{indices_.data(), triangles()}};
  }
  static py::array_t<std::int64_t> pair_array(const std::vector<TrianglePair>& p) {
    py::array_t<std::int64_t> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(2)});
    std::int64_t* o = out.mutable_data();
    for (std::size_t k = 0; k < p.size(); ++k) o[2 * k] = p[k].i, o[2 * k + 1] = p[k].j;
    return out;
  }
  py::array_t<std::int64_t> self_intersections(int threads) const {
    std::vector<TrianglePair> p;
    IntersectOptions opt;
    opt.threads = threads;
    {
      py::gil_scoped_release unlocked;
      const MeshArrays a = arrays();
      p = ::rayproof::self_intersections(a.vertices, a.indices, opt);
    }
    return pair_array(p);
  }
  py::array_t<std::int64_t> intersecting_pairs(const PyMesh& other, int threads) const {
    std::vector<TrianglePair> p;
    IntersectOptions opt;
    opt.threads = threads;
    {
      py::gil_scoped_release unlocked;
      p = ::rayproof::intersecting_pairs(arrays(), other.arrays(), opt);
    }
    return pair_array(p);
  }

  /// winding(): on a closed oriented mesh the exact winding number per point (int32; INT32_MIN on
  /// the surface, 0 when invalid); on any other mesh, or with with_bound, the generalized winding
  /// number and its bound as two float64 arrays (w NaN on the surface and for invalid points).
  py::object winding(py::handle points, double tolerance, bool with_bound, int threads) {
    const Rows p = rows_of(points, "points", 3, true);
    const std::size_t n = p.broadcast ? 1 : p.rows;
    const ExactMesh& any = closed("automatic");
    if (!(tolerance > 0)) throw py::value_error("tolerance: must be positive");
    if (with_bound || !any.closed() || !any.oriented()) {
      py::array_t<double> w(static_cast<py::ssize_t>(n)), bound(static_cast<py::ssize_t>(n));
      const double* xyz = p.data.data();
      double *wo = w.mutable_data(), *bo = bound.mutable_data();
      {
        py::gil_scoped_release unlocked;
        any.winding_values(xyz, n, 3 * sizeof(double), wo, bo, tolerance, threads);
      }
      return py::make_tuple(w, bound);
    }
    const ExactMesh& cm = closed("nonzero");
    py::array_t<std::int32_t> out(static_cast<py::ssize_t>(n));
    std::int32_t* o = out.mutable_data();
    {
      py::gil_scoped_release unlocked;
      for (std::size_t i = 0; i < n; ++i) {
        const double* r = p.row(i);
        o[i] = cm.winding({r[0], r[1], r[2]});
      }
    }
    return out;
  }

  /// segment(): per segment p -> q whether it meets the surface, the first contact's t, triangle,
  /// class, and the endpoints' sides.
  py::dict segment(py::handle ps, py::handle qs) {
    const Rows p = rows_of(ps, "p", 3, true), q = rows_of(qs, "q", 3, true);
    const std::size_t n = common_rows({{"p", &p}, {"q", &q}});
    const ExactMesh& cm = closed("automatic");
    const auto sn = static_cast<py::ssize_t>(n);
    py::array_t<bool> crosses(sn);
    py::array_t<double> t(sn);
    py::array_t<std::int64_t> prim(sn);
    py::array_t<std::uint8_t> codes(sn), pside(sn), qside(sn);
    {
      py::gil_scoped_release unlocked;
      for (std::size_t i = 0; i < n; ++i) {
        const double *a = p.row(i), *b = q.row(i);
        const SegmentHit h = cm.segment({a[0], a[1], a[2]}, {b[0], b[1], b[2]});
        crosses.mutable_data()[i] = h.crosses;
        t.mutable_data()[i] = h.t;
        prim.mutable_data()[i] = h.crosses ? static_cast<std::int64_t>(h.triangle) : -1;
        codes.mutable_data()[i] = static_cast<std::uint8_t>(h.contact);
        pside.mutable_data()[i] = static_cast<std::uint8_t>(h.p_side);
        qside.mutable_data()[i] = static_cast<std::uint8_t>(h.q_side);
      }
    }
    py::dict out;
    out["crosses"] = crosses;
    out["t"] = t;
    out["prim"] = prim;
    out["classes"] = class_names(codes);
    out["codes"] = codes;
    out["p_side"] = pside;
    out["q_side"] = qside;
    return out;
  }

  /// crossings(): every crossing of each ray once, in exact t order, with its direction (+1 in,
  /// -1 out), as flat arrays with offsets; with touches also the touches.
  py::dict crossings(py::handle origins, py::handle directions, double tmin, double tmax, bool touches, int threads) {
    const auto rays = rays_of(origins, directions);
    const std::size_t n = rays.size();
    if (!(tmin <= tmax)) throw py::value_error(fmt::format("tmin {} is not <= tmax {}", tmin, tmax));
    const ExactMesh& cm = closed("automatic");
    std::vector<RayCrossings> res(n);
    {
      py::gil_scoped_release unlocked;
      cm.ray_crossings(rays, res, {tmin, tmax}, threads);
    }
    std::size_t nc = 0, nt = 0;
    for (const auto& r : res) nc += r.crossings.size(), nt += r.touches.size();
    py::array_t<std::int64_t> offsets(static_cast<py::ssize_t>(n + 1)), ray(static_cast<py::ssize_t>(nc)),
        prim(static_cast<py::ssize_t>(nc));
    py::array_t<double> t(static_cast<py::ssize_t>(nc));
    py::array_t<std::int8_t> dir(static_cast<py::ssize_t>(nc));
    py::array_t<bool> valid(static_cast<py::ssize_t>(n));
    py::array_t<std::int64_t> toff(static_cast<py::ssize_t>(n + 1)), tray(static_cast<py::ssize_t>(nt)),
        tprim(static_cast<py::ssize_t>(nt));
    py::array_t<double> tt(static_cast<py::ssize_t>(nt)), tt2(static_cast<py::ssize_t>(nt));
    py::array_t<std::uint8_t> tcodes(static_cast<py::ssize_t>(nt));
    std::size_t k = 0, m = 0;
    offsets.mutable_data()[0] = 0, toff.mutable_data()[0] = 0;
    for (std::size_t i = 0; i < n; ++i) {
      valid.mutable_data()[i] = res[i].valid;
      for (const Crossing& c : res[i].crossings) {
        ray.mutable_data()[k] = static_cast<std::int64_t>(i);
        prim.mutable_data()[k] = static_cast<std::int64_t>(c.triangle);
        t.mutable_data()[k] = c.t;
        dir.mutable_data()[k] = c.direction == CrossingDirection::in ? 1 : -1;
        ++k;
      }
      for (const Touch& h : res[i].touches) {
        tray.mutable_data()[m] = static_cast<std::int64_t>(i);
        tprim.mutable_data()[m] = static_cast<std::int64_t>(h.triangle);
        tt.mutable_data()[m] = h.t;
        tt2.mutable_data()[m] = h.t2;
        tcodes.mutable_data()[m] = static_cast<std::uint8_t>(h.contact);
        ++m;
      }
      offsets.mutable_data()[i + 1] = static_cast<std::int64_t>(k);
      toff.mutable_data()[i + 1] = static_cast<std::int64_t>(m);
    }
    py::dict out;
    out["offsets"] = offsets;
    out["ray"] = ray;
    out["t"] = t;
    out["prim"] = prim;
    out["direction"] = dir;
    out["valid"] = valid;
    if (touches) {
      out["touch_offsets"] = toff;
      out["touch_ray"] = tray;
      out["touch_t"] = tt;
      out["touch_t2"] = tt2;
      out["touch_prim"] = tprim;
      out["touch_classes"] = class_names(tcodes);
      out["touch_codes"] = tcodes;
    }
    return out;
  }

  [[nodiscard]] bool oriented() { return closed("automatic").oriented(); }
  [[nodiscard]] bool is_closed() { return closed("automatic").closed(); }
  [[nodiscard]] std::string rule() { return to_string(closed("automatic").rule()); }

 private:
  /// The ExactMesh of `rule`, built once (GIL released); MeshNotClosedError becomes ValueError.
  const ExactMesh& closed(const std::string& rule) {
    const int k = rule == "automatic" ? 0 : rule == "nonzero" ? 1 : rule == "parity" ? 2 : rule == "winding" ? 3 : -1;
    if (k < 0) throw py::value_error(fmt::format("rule: '{}' is not a rule (automatic, nonzero, parity, winding)", rule));
    LazyClosed& lazy = closed_[k];
    {
      py::gil_scoped_release unlocked;
      std::call_once(lazy.once, [&] {
        try {
          const ContainsRule r = k == 0   ? ContainsRule::automatic
                                 : k == 1 ? ContainsRule::nonzero
                                 : k == 2 ? ContainsRule::parity
                                          : ContainsRule::winding;
          lazy.mesh = std::make_unique<ExactMesh>(VertexArray(vertices_.data(), vertices()),
                                                   IndexArray{indices_.data(), triangles()}, r);
        } catch (const std::invalid_argument& e) {
          lazy.error = e.what();
        }
      });
    }
    if (!lazy.mesh) throw py::value_error(fmt::format("mesh: {}", lazy.error));
    return *lazy.mesh;
  }

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
  LazyClosed closed_[4];  ///< automatic, nonzero, parity, winding
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
           "offsets[i]:offsets[i+1]). The GIL is released.")
      .def("contains", &PyMesh::contains, "points"_a, "rule"_a = "automatic", "threads"_a = 0,
           "Side of each point ((n, 3) or (3,)), decided with certainty: a uint8 array, "
           "rayproof.OUTSIDE (0), INSIDE (1), SURFACE (2: on a triangle, edges and vertices included) or "
           "INVALID (3: a NaN or infinite coordinate). rule: 'automatic' (closed mesh: nonzero winding number "
           "when oriented, else parity; any other mesh: 'winding'), 'nonzero', 'parity' (these two raise "
           "ValueError naming an open edge on a mesh that is not closed) or 'winding' (inside where the "
           "generalized winding number > 1/2; exactly 1/2 is outside). The rule used: Mesh.rule. float64 "
           "C-contiguous points are read in place; the GIL is released. docs/contains.md.")
      .def("distance", &PyMesh::distance, "points"_a, "threads"_a = 0,
           "Distance from each point ((n, 3) or (3,)) to the mesh: float64, the exact distance correctly "
           "rounded; NaN for a point with a NaN or infinite coordinate. The GIL is released. docs/distance.md.")
      .def("signed_distance", &PyMesh::signed_distance, "points"_a, "threads"_a = 0,
           "The distance with the side's sign (Mesh.contains, exact): negative inside, 0 on the surface, "
           "positive outside, NaN for invalid points. The GIL is released.")
      .def("closest_points", &PyMesh::closest_points, "points"_a, "side"_a = false, "threads"_a = 0,
           "A dict: 'points' (n, 3) the closest points, 'triangles' (int64, a nearest triangle, the lowest index "
           "among exact ties; -1 for invalid points), 'barycentric' (n, 3) weights of that triangle's vertices, "
           "'distance'; with side=True 'side' (uint8 codes as contains). The GIL is released.")
      .def("winding", &PyMesh::winding, "points"_a, "tolerance"_a = 1e-6, "with_bound"_a = false, "threads"_a = 0,
           "Winding number at each point. On a closed oriented mesh (and with_bound False): the exact integer "
           "(int32; -2**31 on the surface). On any other mesh, or with with_bound: a tuple (w, bound) of float64 "
           "arrays, the generalized winding number and a guaranteed bound (|w_exact - w| <= bound <= tolerance "
           "unless the direct evaluation of every triangle is coarser); w NaN on the surface (bound 0) and for "
           "invalid points (bound inf). The GIL is released.")
      .def("segment", &PyMesh::segment, "p"_a, "q"_a,
           "Whether each closed segment p -> q meets the surface (exact) and its first contact: a dict of "
           "'crosses', 't' (in [0, 1], within a few ulps; NaN for none), 'prim' (-1 for none), 'classes', "
           "'codes' (interior, edge, vertex, coplanar), 'p_side', 'q_side' (as contains).")
      .def("crossings", &PyMesh::crossings, "origins"_a, "directions"_a, "tmin"_a = 0.0, "tmax"_a = kInf,
           "touches"_a = false, "threads"_a = 0,
           "Every point where each ray passes through the surface, once (a shared edge or vertex is one "
           "crossing), in exact t order, decided exactly (any mesh: open meshes and soups too). Returns a dict "
           "of flat arrays 't' (within one ulp of the exact t), 'prim', 'direction' (int8: +1 in, against the "
           "triangle's normal; -1 out), 'ray', 'offsets' (r + 1: ray i's crossings are offsets[i]:offsets[i+1]) "
           "and 'valid' (per ray: False for a NaN or infinite component or a zero direction). With touches: "
           "'touch_offsets', 'touch_ray', 'touch_t', 'touch_t2', 'touch_prim', 'touch_classes', 'touch_codes' "
           "(edge or vertex: a silhouette point; coplanar: the ray along a triangle from touch_t to touch_t2). "
           "A crossing counts when tmin <= t <= tmax. The GIL is released. docs/contains.md, 'Crossings'.")
      .def("self_intersections", &PyMesh::self_intersections, "threads"_a = 0,
           "The pairs of triangles that intersect, exact, as CGAL Polygon_mesh_processing::self_intersections "
           "defines them: a (k, 2) int64 array of triangle numbers (i < j), sorted. Triangles that share a vertex "
           "index count only where they meet beyond it; sharing an edge (two indices), only where they are "
           "coplanar and overlap with positive area; equal coordinates under other indices are not shared. A "
           "zero-area triangle i is the row (i, i) and is in no other row. The GIL is released. docs/intersect.md.")
      .def("intersecting_pairs", &PyMesh::intersecting_pairs, "other"_a, "threads"_a = 0,
           "The pairs (i of this mesh, j of other) of closed triangles that share a point, exact: a (k, 2) int64 "
           "array, sorted (zero-area triangles as the segments or points they are). The GIL is released.")
      .def_property_readonly("oriented", &PyMesh::oriented,
                             "Whether the mesh is closed and oriented (integer winding numbers defined).")
      .def_property_readonly("closed", &PyMesh::is_closed, "Whether every edge is used by an even number of triangles.")
      .def_property_readonly("rule", &PyMesh::rule,
                             "The rule contains() applies by default: 'nonzero', 'parity' or 'winding'.");
  m.attr("OUTSIDE") = static_cast<int>(Side::outside);
  m.attr("INSIDE") = static_cast<int>(Side::inside);
  m.attr("SURFACE") = static_cast<int>(Side::surface);
  m.attr("INVALID") = static_cast<int>(Side::invalid);
}

}  // namespace rayproof::python
