#pragma once
/// Per-primitive kernels for the scene traversal (internal to rayproof_scene). A kernel is
/// prepared once per ray, then lists the crossings (at most 2) of one primitive.
#include <optional>
#include <type_traits>

#include "methods/primitive_of.h"
#include "rayproof/certified_triangle.h"
#include "rayproof/triangle.h"
#include "rayproof/triangle_watertight.h"
#include "scene/accel.h"
#include "scene/leaf_simd.h"

namespace rayproof::scene::detail {

struct Crossing {
  Contact contact;
  double t;
  double b1 = kNaN<double>, b2 = kNaN<double>;  ///< a triangle's barycentrics, where the kernel has them
};

/// The crossings a primitive's class carries, from its class and T, T2 (docs/cases.md): a quadric or
/// box hit crosses twice, inside crosses at the exit, tangent and graze once.
inline int crossings_of(Contact c, double t, double t2, Crossing out[2]) {
  switch (c) {
    case Contact::interior: case Contact::edge: case Contact::vertex: case Contact::tangent:
    case Contact::graze: case Contact::rim:
      out[0] = {c, t};
      return 1;
    case Contact::coplanar:  // a triangle touched along a segment: the first touch
      if (t != t) return 0;
      out[0] = {c, t};
      return 1;
    case Contact::hit:
      out[0] = {c, t};
      if (t2 == t2 && t2 != t) return out[1] = {c, t2}, 2;
      return 1;
    case Contact::inside:
      out[0] = {c, t2};
      return 1;
    default:
      return 0;
  }
}

/// A triangle kernel's crossings with its barycentrics (coplanar: none, the touch is a segment).
template <class T>
inline int crossings_of(const TriangleHit<T>& h, Crossing out[2]) {
  const int n = crossings_of(h.contact, double(h.t), double(h.t2), out);
  if (n == 1 && h.contact != Contact::coplanar) out[0].b1 = double(h.b1), out[0].b2 = double(h.b2);
  return n;
}

/// Möller–Trumbore's miss screen: the same arithmetic as intersect_moller_trumbore up to b1, b2
/// and t, so a `true` here is a case the full kernel classes miss or behind (no crossing). A
/// nonzero det, in-range barycentrics and t >= 0 (or NaN) go on to the full kernel, which adds
/// the degenerate / coplanar / invalid screening and the class.
template <class T>
[[nodiscard]] inline bool mt_surely_no_crossing(const Ray<T>& ray, const Triangle<T>& tri) {
  const Vec3<T> e1 = tri.p1 - tri.p0, e2 = tri.p2 - tri.p0;
  const Vec3<T> s1 = cross(ray.d, e2);
  const T det = dot(s1, e1);
  if (det == T(0)) return false;
  const T inv = T(1) / det;
  const Vec3<T> s = ray.o - tri.p0;
  const T b1 = dot(s1, s) * inv;
  if (!(b1 >= T(0))) return true;  // classify_barycentric: b1 < 0 or NaN is a miss
  const Vec3<T> s2 = cross(s, e1);
  const T b2 = dot(s2, ray.d) * inv;
  if (!(b2 >= T(0) && T(1) - b1 - b2 >= T(0))) return true;
  return dot(s2, e2) * inv < T(0);  // behind
}

/// Any registry method, through the case interface (io::Case in, CaseResult out).
struct GenericKernel {
  const Scene& s;
  const Method& m;
  Ray<double> ray{};

  void prepare(const Ray<double>& r) { ray = r; }
  int crossings(const LeafPrim& p, Crossing out[2]) const { return crossings(p.id, out); }
  /// Float methods are run on the float-rounded ray (docs/cases.md): traverse with that one.
  [[nodiscard]] Ray<double> traversal_ray() const {
    if (m.precision != Precision::float32) return ray;
    return {ray.o.template cast<float>().template cast<double>(), ray.d.template cast<float>().template cast<double>()};
  }
  int crossings(std::uint32_t id, Crossing out[2]) const {
    io::Case c;
    auto put = [&](int at, const Vec3<double>& v) { c.v[at] = v.x, c.v[at + 1] = v.y, c.v[at + 2] = v.z; };
    put(0, ray.o), put(3, ray.d);
    std::uint32_t k;
    switch (s.kind_of(id, k)) {
      case PrimKind::triangle: {
        const Triangle<double> t = s.triangle(k);
        c.kind = io::Kind::triangle, put(6, t.p0), put(9, t.p1), put(12, t.p2);
        break;
      }
      case PrimKind::sphere: c.kind = io::Kind::sphere, put(6, s.spheres[k].center), c.v[9] = s.spheres[k].radius; break;
      case PrimKind::ellipsoid: c.kind = io::Kind::ellipsoid, put(6, s.ellipsoids[k].center), put(9, s.ellipsoids[k].semi_axes); break;
      case PrimKind::disk:
        c.kind = io::Kind::disk, put(6, s.disks[k].center), put(9, s.disks[k].normal), c.v[12] = s.disks[k].radius;
        break;
      case PrimKind::box: c.kind = io::Kind::box, put(6, s.boxes[k].lo), put(9, s.boxes[k].hi); break;
    }
    if (!m.supports(c.kind)) return 0;
    const io::CaseResult r = m.run(c);
    return crossings_of(r.contact, r.t.value_or(kNaN<double>), r.t2.value_or(kNaN<double>), out);
  }
};

/// The robust and certified methods' triangle kernels, compiled: `robust` is the watertight test
/// on float inputs in double arithmetic; `certified` the certified filter with an exact fallback
/// when it cannot decide (SceneMethod::triangle_fallback when given, else the registry method).
enum class TriAlgo { moller_trumbore, cramer, watertight, robust, certified };

template <class T, TriAlgo A>
struct CompiledKernel {
  const Scene& s;
  const Vec3<double>* verts;  ///< the triangles' vertices (the scene's, or a user's array in place)
  std::uint32_t ntri;         ///< global numbers below ntri are triangles
  const Method* fallback = nullptr;  ///< robust, certified: the registry method (other kinds, undecided)
  TriangleFallback tri_fallback = nullptr;  ///< certified: the typed exact fallback, before `fallback`
  Ray<T> ray{};
  std::optional<WatertightRay<T>> wr{};
  Ray<double> ray_d{};

  // robust: the leaf kernels' per-ray part, made at the first leaf the ray reaches (leaf_ready()),
  // not in prepare(): a ray that reaches no leaf (it misses the root box, or passes between the
  // leaves' boxes) does not pay for it. The values are the same whenever they are made.
  mutable bool ray_ok = false;                                ///< robust: the float ray is valid
  mutable std::optional<WatertightRay<float, double>> wr_robust{};  ///< robust: the front door's per-ray part
  mutable RobustLaneRay lane_ray{};  ///< robust, certified: the per-ray part for the group kernels (leaf_simd.h)
  mutable bool leaf_part_made = true;

  void prepare(const Ray<double>& r) {
    ray = {r.o.template cast<T>(), r.d.template cast<T>()};
    ray_d = r;
    if constexpr (A == TriAlgo::watertight) wr.emplace(ray);
    if constexpr (A == TriAlgo::robust) {
      leaf_part_made = false;
      if (!lazy_leaf_setup()) leaf_ready();
    }
    if constexpr (A == TriAlgo::certified) {
      if (certified_screen()) certified_lane_ray(r, lane_ray);  // (off by default: leaf_simd.h)
    }
  }
  /// robust: makes the leaf kernels' per-ray part if not made yet for this ray (every leaf path
  /// calls it before reading ray_ok, wr_robust or lane_ray).
  void leaf_ready() const {
    if constexpr (A == TriAlgo::robust) {
      if (leaf_part_made) return;
      leaf_part_made = true;
      ray_ok = ray.valid();
      if (ray_ok) {
        wr_robust.emplace(ray);
        for (int k = 0; k < 3; ++k) lane_ray.o[k] = wr_robust->o[k], lane_ray.d[k] = wr_robust->d[k];
        lane_ray.kx = wr_robust->kx, lane_ray.ky = wr_robust->ky, lane_ray.kz = wr_robust->kz;
        lane_ray.edge_k_double = wr_robust->edge_k;
        // The float screen's constants: only its users need them (the SSE path; AVX2 when its
        // screen is switched on). robust_group_avx2 reads o, d, the axes and edge_k_double only.
        if (leaf_simd() != LeafSimd::avx2 || robust_screen_avx2()) finish_lane_ray(lane_ray);
      }
    }
  }
  /// The ray the kernel intersects, in double (a float kernel's float-rounded ray): the one the
  /// BVH traversal must not cull boxes of.
  [[nodiscard]] Ray<double> traversal_ray() const { return {ray.o.template cast<double>(), ray.d.template cast<double>()}; }
  /// Triangle i by global number (the scene's index list: only for scenes, not in-place meshes).
  [[nodiscard]] Triangle<double> triangle_d(std::uint32_t i) const {
    const auto& t = s.mesh.triangles[i];
    return {verts[t[0]], verts[t[1]], verts[t[2]]};
  }
  [[nodiscard]] Triangle<T> tri(std::uint32_t i) const {
    const Triangle<double> t = triangle_d(i);
    return {t.p0.template cast<T>(), t.p1.template cast<T>(), t.p2.template cast<T>()};
  }
  int crossings(std::uint32_t id, Crossing out[2]) const;
  /// The same from a leaf-order record: the triangle's vertices straight from its indices.
  int crossings(const LeafPrim& p, Crossing out[2]) const;
  /// A triangle's crossings from its vertices in T (float kernels: the float-rounded vertices, as
  /// a leaf group holds them); not for certified.
  int triangle_crossings(const Triangle<T>& t, Crossing out[2]) const;

 private:
  /// certified: the filter's answer, else the exact fallback (typed, or the registry method's).
  int certified_crossings(const Triangle<double>& t, std::uint32_t id, Crossing out[2]) const {
    if (const auto h = certified::triangle(ray_d, t)) return crossings_of(h->contact, h->t, h->t2, out);
    if (tri_fallback) {
      const Hit<double> h = tri_fallback(ray_d, t);
      return crossings_of(h.contact, h.t, h.t2, out);
    }
    return GenericKernel{s, *fallback, ray_d}.crossings(id, out);
  }
};

template <class T, TriAlgo A>
int CompiledKernel<T, A>::crossings(std::uint32_t id, Crossing out[2]) const {
    if constexpr (A == TriAlgo::robust || A == TriAlgo::certified) {
      if (id >= ntri) return GenericKernel{s, *fallback, ray_d}.crossings(id, out);
    }
    if (id < ntri) {
      if constexpr (A == TriAlgo::certified) return certified_crossings(triangle_d(id), id, out);
      return triangle_crossings(tri(id), out);
    }
    std::uint32_t k;
    Hit<T> h;
    switch (s.kind_of(id, k)) {
      case PrimKind::sphere: h = intersect(ray, Sphere<T>{s.spheres[k].center.template cast<T>(), T(s.spheres[k].radius)}); break;
      case PrimKind::ellipsoid:
        h = intersect(ray, Ellipsoid<T>{s.ellipsoids[k].center.template cast<T>(), s.ellipsoids[k].semi_axes.template cast<T>()});
        break;
      case PrimKind::disk: {
        const auto& d = s.disks[k];
        h = intersect(ray, Disk<T>{d.center.template cast<T>(), d.normal.template cast<T>(), T(d.radius)});
        break;
      }
      case PrimKind::box: h = intersect(ray, Box<T>{s.boxes[k].lo.template cast<T>(), s.boxes[k].hi.template cast<T>()}); break;
      case PrimKind::triangle: break;
    }
    return crossings_of(h.contact, double(h.t), double(h.t2), out);
}

template <class T, TriAlgo A>
int CompiledKernel<T, A>::crossings(const LeafPrim& p, Crossing out[2]) const {
  if (p.id >= ntri) return crossings(p.id, out);
  const Vec3<double>* v = verts;
  if constexpr (A == TriAlgo::certified) {
    return certified_crossings(Triangle<double>{v[p.v[0]], v[p.v[1]], v[p.v[2]]}, p.id, out);
  } else {
    return triangle_crossings({v[p.v[0]].template cast<T>(), v[p.v[1]].template cast<T>(), v[p.v[2]].template cast<T>()}, out);
  }
}

template <class T, TriAlgo A>
int CompiledKernel<T, A>::triangle_crossings(const Triangle<T>& t, Crossing out[2]) const {
      TriangleHit<T> h;
      if constexpr (A == TriAlgo::robust) {
        // The registry's front door, intersect_watertight<float, double>(ray, t), step by step with
        // its per-ray parts (ray validity, the axis permutation) computed once in prepare(): the
        // same operations on the same values, so the same result (tests/scene_test.cpp checks it
        // against the registry method crossing by crossing, on leak rays too). No step is skipped:
        // an earlier prepared-ray *miss screen* (the watertight test alone first) leaked.
        leaf_ready();
        if (!ray_ok || !triangle_finite(t)) return 0;  // invalid
        const Vec3<double> p0 = t.p0.template cast<double>(), p1 = t.p1.template cast<double>(),
                           p2 = t.p2.template cast<double>();
        const Vec3<double> n = cross(p1 - p0, p2 - p0);
        if (is_zero(n)) return 0;  // degenerate
        const double dn = dot(ray.d.template cast<double>(), n);
        if (dn == 0.0) {
          h = intersect_watertight<float, double>(ray, t);  // parallel or coplanar: the front door decides
        } else {
          h = intersect_watertight(*wr_robust, t);
          // Bounded zeros' undecided case: the front door's contact at the plane's t.
          if (h.contact == Contact::parallel) h = rayproof::detail::undecided_contact<float>(wr_robust->o, p0, n, dn);
        }
      } else if constexpr (A == TriAlgo::watertight) {
        h = intersect_watertight(*wr, t);
        if (h.contact == Contact::parallel) h = intersect_watertight(ray, t);  // coplanar or degenerate
      } else if constexpr (A == TriAlgo::cramer) {
        h = intersect_cramer(ray, t);
      } else {
        if (mt_surely_no_crossing(ray, t)) return 0;
        h = intersect_moller_trumbore(ray, t);
      }
      return crossings_of(h, out);
}

}  // namespace rayproof::scene::detail
