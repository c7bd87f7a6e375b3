// rayproof::MeshCaster (include/rayproof/scene/mesh_caster.h) on users' arrays: every vertex and index
// layout gives the hits of brute force over every triangle with the same kernel; robust and
// certified do not leak on closed meshes; any, all and the batches agree with closest; bad input
// throws MeshInputError.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "rayproof/certified/intersect.h"
#include "rayproof/certified_triangle.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/triangle_moller_trumbore.h"
#include "rayproof/triangle_watertight.h"
#include "scene/scene.h"
#include "scene/watertight.h"

using namespace rayproof;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A mesh as the caster reads it: vertices in double (float layouts: the float values).
struct Plain {
  std::vector<Vec3<double>> v;
  std::vector<std::array<std::uint32_t, 3>> f;
};

/// A closed, irregular mesh: an icosphere (320 triangles) with its vertices pushed radially.
Plain test_mesh() {
  const mesh::Mesh m = scene::bumpy_sphere(300);
  return {m.vertices, m.triangles};
}

// ---- brute force over every triangle, with the kernel the method names ----

struct Crossing {
  Contact c;
  double t, b1, b2;
};

/// The crossing a kernel's triangle answer carries (as docs/cases.md and the scene queries count it):
/// interior, edge and vertex cross at t; coplanar at its first touch; anything else does not cross.
template <class H>
std::optional<Crossing> crossing_of(const H& h, double b1, double b2) {
  switch (h.contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex: return Crossing{h.contact, double(h.t), b1, b2};
    case Contact::coplanar:
      if (h.t != h.t) return std::nullopt;
      return Crossing{h.contact, double(h.t), kNaN<double>, kNaN<double>};
    default: return std::nullopt;
  }
}

std::optional<Crossing> brute_one(cast::Float, const Ray<double>& r, const Triangle<double>& t) {
  const Ray<float> rf{r.o.cast<float>(), r.d.cast<float>()};
  const TriangleHit<float> h = intersect_moller_trumbore(rf, Triangle<float>{t.p0.cast<float>(), t.p1.cast<float>(), t.p2.cast<float>()});
  return crossing_of(h, h.b1, h.b2);
}
std::optional<Crossing> brute_one(cast::Robust, const Ray<double>& r, const Triangle<double>& t) {
  const Ray<float> rf{r.o.cast<float>(), r.d.cast<float>()};
  const TriangleHit<float> h =
      intersect_watertight<float, double>(rf, Triangle<float>{t.p0.cast<float>(), t.p1.cast<float>(), t.p2.cast<float>()});
  return crossing_of(h, h.b1, h.b2);
}
/// certified: the filter, else certified::intersect (the filter again, then the exact fallback).
std::optional<Crossing> brute_one(cast::Certified, const Ray<double>& r, const Triangle<double>& t) {
  if (const auto h = certified::triangle(r, t)) return crossing_of(*h, kNaN<double>, kNaN<double>);
  return crossing_of(certified::intersect(r, t), kNaN<double>, kNaN<double>);
}

/// Every crossing in [tmin, tmax], sorted by t then triangle.
template <class M>
std::vector<MeshHit> brute_all(const Plain& m, const Ray<double>& r, TRange q) {
  std::vector<MeshHit> out;
  if (!r.valid()) return out;
  for (std::uint32_t i = 0; i < m.f.size(); ++i) {
    const auto& f = m.f[i];
    const auto c = brute_one(M{}, r, {m.v[f[0]], m.v[f[1]], m.v[f[2]]});
    if (c && c->t >= q.tmin && c->t <= q.tmax) out.push_back({i, c->c, c->t, c->b1, c->b2});
  }
  std::sort(out.begin(), out.end(), [](const MeshHit& a, const MeshHit& b) {
    return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
  });
  return out;
}

/// Same triangle, class and t, and the same barycentrics (both NaN counts as the same).
void expect_same(const MeshHit& a, const MeshHit& b, const std::string& where) {
  auto same = [](double x, double y) { return x == y || (x != x && y != y); };
  EXPECT_EQ(a.triangle, b.triangle) << where;
  EXPECT_EQ(a.contact, b.contact) << where;
  EXPECT_TRUE(same(a.t, b.t)) << where << ": t " << a.t << " vs " << b.t;
  EXPECT_TRUE(same(a.b1, b.b1) && same(a.b2, b.b2)) << where << ": barycentrics";
}

/// Rays: from random points in and around the mesh towards random points near it, towards its
/// vertices and edge midpoints from inside, with random ranges (some rays from inside start past
/// their first crossing).
struct RaySet {
  std::vector<Ray<double>> rays;
  std::vector<TRange> ranges;
};
RaySet test_rays(const Plain& m, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  std::uniform_int_distribution<std::size_t> pick(0, m.f.size() - 1);
  RaySet s;
  for (std::size_t i = 0; i < n; ++i) {
    Ray<double> r;
    if (i % 3 == 0) {  // from inside towards a vertex or an edge midpoint
      const auto& f = m.f[pick(rng)];
      const Vec3<double> target = i % 2 ? m.v[f[0]] : (m.v[f[0]] + m.v[f[1]]) * 0.5;
      r.o = {u(rng) * 0.1, u(rng) * 0.1, u(rng) * 0.1};
      r.d = target - r.o;
    } else {
      r.o = {u(rng), u(rng), u(rng)};
      r.d = Vec3<double>{u(rng), u(rng), u(rng)} * 0.7 - r.o;
    }
    s.rays.push_back(r);
    const int kind = int(i % 4);
    s.ranges.push_back(kind == 0 ? TRange{} : kind == 1 ? TRange{0.5, kInf} : kind == 2 ? TRange{0, 0.8} : TRange{0.2, 1.5});
  }
  return s;
}

// ---- the layouts a user may hand over ----

struct InterleavedF {  // position, normal, colour: stride 28
  float p[3];
  float n[3];
  std::uint8_t rgba[4];
};
struct InterleavedD {  // position and texture coordinates: stride 40
  double p[3];
  double uv[2];
};
struct Face {  // indices and a material: stride 16
  std::uint32_t v[3];
  std::uint32_t material;
};

/// The mesh's vertices rounded to float (what the caster sees from a float layout).
Plain rounded_to_float(Plain m) {
  for (auto& p : m.v) p = p.cast<float>().cast<double>();
  return m;
}

/// Whether the BVH must give exactly brute force's crossings on ray i. Float's textbook slab test
/// may drop a crossing that the float kernel puts, by its rounding, just outside the triangle's box
/// (rays aimed at vertices and edges, every third ray of test_rays): there its crossings are a
/// subset of brute force's.
template <class M>
bool exact_set(std::size_t i) {
  return !std::is_same_v<M, cast::Float> || i % 3 != 0;
}

template <class M>
void check_against_brute_force(const MeshCaster<M>& caster, const Plain& seen, const RaySet& rs, const std::string& name) {
  ASSERT_EQ(caster.triangle_count(), seen.f.size());
  std::vector<MeshHit> batch(rs.rays.size());
  caster.closest(rs.rays, rs.ranges, batch, 2);
  std::vector<std::uint8_t> any(rs.rays.size());
  caster.any(rs.rays, rs.ranges, any, 2);
  for (std::size_t i = 0; i < rs.rays.size(); ++i) {
    const std::string where = name + " ray " + std::to_string(i);
    const auto brute = brute_all<M>(seen, rs.rays[i], rs.ranges[i]);
    const auto all = caster.all(rs.rays[i], rs.ranges[i]);
    const MeshHit c = caster.closest(rs.rays[i], rs.ranges[i]);
    if (exact_set<M>(i)) {
      ASSERT_EQ(all.size(), brute.size()) << where;
      for (std::size_t k = 0; k < all.size(); ++k) expect_same(all[k], brute[k], where + " crossing " + std::to_string(k));
      expect_same(c, brute.empty() ? MeshHit{} : brute.front(), where + " closest");
    } else {
      // Closest-hit pruning may also skip such a box that all() visits: closest() is one of the
      // crossings, not necessarily all()'s first.
      auto expect_in_brute = [&](const MeshHit& h, const std::string& what) {
        const auto it = std::find_if(brute.begin(), brute.end(), [&](const MeshHit& b) { return b.triangle == h.triangle; });
        ASSERT_NE(it, brute.end()) << what << ": triangle " << h.triangle << " is not a brute-force crossing";
        expect_same(h, *it, what);
      };
      for (const MeshHit& h : all) expect_in_brute(h, where + " crossing");
      for (std::size_t k = 1; k < all.size(); ++k) EXPECT_LE(all[k - 1].t, all[k].t) << where;
      if (c.hit()) expect_in_brute(c, where + " closest");
      EXPECT_EQ(c.hit(), !all.empty()) << where;
    }
    expect_same(batch[i], c, where + " batch");
    EXPECT_EQ(caster.any(rs.rays[i], rs.ranges[i]), c.hit()) << where;
    EXPECT_EQ(any[i], c.hit() ? 1 : 0) << where;
  }
}

template <class M>
void check_every_layout(const std::string& name) {
  const Plain m = test_mesh();
  const Plain mf = rounded_to_float(m);
  const RaySet rs = test_rays(m, 240, 7);
  // Packed doubles and packed indices: read in place.
  std::vector<double> pd;
  for (const auto& p : m.v) pd.insert(pd.end(), {p.x, p.y, p.z});
  std::vector<std::uint32_t> pi;
  for (const auto& f : m.f) pi.insert(pi.end(), f.begin(), f.end());
  const MeshCaster<M> packed(VertexArray(pd.data(), m.v.size()), IndexArray{pi.data(), m.f.size()});
  EXPECT_FALSE(packed.copies_vertices());
  check_against_brute_force(packed, m, rs, name + " packed double");
  // Packed floats, strided indices.
  std::vector<float> pf;
  for (const auto& p : m.v) pf.insert(pf.end(), {float(p.x), float(p.y), float(p.z)});
  std::vector<Face> faces;
  for (std::uint32_t i = 0; i < m.f.size(); ++i) faces.push_back({{m.f[i][0], m.f[i][1], m.f[i][2]}, i % 5});
  const MeshCaster<M> packed_f(VertexArray(pf.data(), m.v.size()), IndexArray{faces[0].v, faces.size(), sizeof(Face)});
  EXPECT_TRUE(packed_f.copies_vertices());
  check_against_brute_force(packed_f, mf, rs, name + " packed float");
  // Interleaved floats (stride 28) and doubles (stride 40).
  std::vector<InterleavedF> vf;
  for (const auto& p : m.v) vf.push_back({{float(p.x), float(p.y), float(p.z)}, {0, 0, 1}, {1, 2, 3, 4}});
  const MeshCaster<M> inter_f(VertexArray(vf[0].p, vf.size(), sizeof(InterleavedF)), IndexArray{pi.data(), m.f.size()});
  check_against_brute_force(inter_f, mf, rs, name + " interleaved float");
  std::vector<InterleavedD> vd;
  for (const auto& p : m.v) vd.push_back({{p.x, p.y, p.z}, {0.25, 0.75}});
  const MeshCaster<M> inter_d(VertexArray(vd[0].p, vd.size(), sizeof(InterleavedD)),
                              IndexArray{faces[0].v, faces.size(), sizeof(Face)});
  EXPECT_TRUE(inter_d.copies_vertices());
  check_against_brute_force(inter_d, m, rs, name + " interleaved double");
}

}  // namespace

TEST(MeshCaster, FloatMatchesBruteForceOnEveryLayout) { check_every_layout<cast::Float>("float"); }
TEST(MeshCaster, RobustMatchesBruteForceOnEveryLayout) { check_every_layout<cast::Robust>("robust"); }
TEST(MeshCaster, CertifiedMatchesBruteForceOnEveryLayout) { check_every_layout<cast::Certified>("certified"); }

TEST(MeshCaster, RobustAndCertifiedDoNotLeakOnClosedMeshes) {
  // Rays from interior points to every vertex and edge midpoint (src/scene/watertight.cpp) of
  // two closed meshes; float is counted too, to show that the rays find leaks where there are any.
  for (const std::size_t tris : {1280u, 5120u}) {
    const mesh::Mesh m = scene::bumpy_sphere(tris);
    std::vector<double> pd;
    for (const auto& p : m.vertices) pd.insert(pd.end(), {p.x, p.y, p.z});
    const VertexArray v(pd.data(), m.vertices.size());
    const IndexArray ix{m.triangles[0].data(), m.triangles.size()};
    const auto targets = scene::leak_targets(m);
    std::vector<Ray<double>> rays;
    for (const Vec3<double> inside : {scene::volume_centroid(m), Vec3<double>{0.1, -0.05, 0.2}}) {
      const auto r = scene::leak_rays(inside, targets);
      rays.insert(rays.end(), r.begin(), r.end());
    }
    auto leaks = [&](const auto& caster) {
      std::vector<MeshHit> hits(rays.size());
      caster.closest(rays, {}, hits, 2);
      return std::count_if(hits.begin(), hits.end(), [](const MeshHit& h) { return !h.hit(); });
    };
    EXPECT_EQ(leaks(MeshCaster<cast::Robust>(v, ix)), 0) << tris << " triangles";
    EXPECT_EQ(leaks(MeshCaster<cast::Certified>(v, ix)), 0) << tris << " triangles";
    EXPECT_GT(leaks(MeshCaster<cast::Float>(v, ix)), 0) << tris << " triangles: the leak rays found no float leak";
  }
}

TEST(MeshCaster, CertifiedUsesTheExactFallbackWhereTheFilterCannotDecide) {
  // Cases of `rayproof gen tri_extreme_scale --seed 3` that the filter leaves to GMP: vertex
  // contacts at magnitudes 1e152 and 1e-146.
  const double cases[2][15] = {
      {-7.414229726884761e+152, 2.1604378012114536e+152, -1.3093562431584567e+151, 1.3093562431584567e+152,
       -1.0474849945267654e+152, 2.094969989053531e+152, -6.284909967160592e+152, -7.332394961687358e+152, 0.0,
       -7.332394961687358e+152, 2.094969989053531e+152, 0.0, -6.284909967160592e+152, 3.666197480843679e+152, 0.0},
      {7.210627397495387e-146, 7.120690070953959e-146, 1.0464012427167926e-145, 9.164809090498814e-151,
       -3.818670454374506e-151, 9.164809090498814e-151, -8.759113541426067e-147, 1.1011457023507055e-145,
       2.2523434820809885e-146, 8.383722961079235e-146, 6.631900252794022e-146, 1.1637107990751774e-145,
       -7.758071993834516e-146, 1.5265883600771145e-145, 6.25650967244719e-146}};
  for (const auto& c : cases) {
    const Ray<double> r{{c[0], c[1], c[2]}, {c[3], c[4], c[5]}};
    const Triangle<double> t{{c[6], c[7], c[8]}, {c[9], c[10], c[11]}, {c[12], c[13], c[14]}};
    ASSERT_FALSE(certified::triangle(r, t)) << c[0] << ": the filter decides this case now: pick one that needs the fallback";
    const std::vector<std::uint32_t> f = {0, 1, 2};
    const MeshCaster<cast::Certified> caster(VertexArray(c + 6, 3), IndexArray{f.data(), 1});
    const auto exact = brute_one(cast::Certified{}, r, t);  // the exact answer, through certified::intersect
    ASSERT_TRUE(exact);
    const MeshHit h = caster.closest(r);
    EXPECT_EQ(h.triangle, 0u);
    EXPECT_EQ(h.contact, exact->c);
    EXPECT_EQ(h.t, exact->t);
  }
}

TEST(MeshCaster, InvalidRaysAndEmptyMeshes) {
  const std::vector<double> v = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::uint32_t> f = {0, 1, 2};
  const MeshCaster<cast::Robust> one(VertexArray(v.data(), 3), IndexArray{f.data(), 1});
  EXPECT_EQ(one.closest({{0.2, 0.2, 1}, {0, 0, -1}}).triangle, 0u);
  const MeshHit bad = one.closest({{0.2, 0.2, 1}, {0, 0, 0}});
  EXPECT_FALSE(bad.hit());
  EXPECT_EQ(bad.contact, Contact::invalid);
  EXPECT_FALSE(one.any({{kNaN<double>, 0.2, 1}, {0, 0, -1}}));
  EXPECT_TRUE(one.all({{0.2, 0.2, 1}, {0, 0, kInf}}).empty());
  // No triangles (null pointers with zero counts): every ray misses.
  const MeshCaster<cast::Float> none(VertexArray(static_cast<const float*>(nullptr), 0), IndexArray{nullptr, 0});
  EXPECT_EQ(none.triangle_count(), 0u);
  EXPECT_FALSE(none.closest({{0, 0, 1}, {0, 0, -1}}).hit());
  EXPECT_FALSE(none.any({{0, 0, 1}, {0, 0, -1}}));
  // A degenerate triangle is never hit.
  const std::vector<double> line = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  const MeshCaster<cast::Certified> flat(VertexArray(line.data(), 3), IndexArray{f.data(), 1});
  EXPECT_FALSE(flat.closest({{1, 0, 1}, {0, 0, -1}}).hit());
}

namespace {
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const MeshInputError& e) {
    return e.what();
  }
  return "(no error)";
}
}  // namespace

TEST(MeshCaster, BadInputThrowsWithAMessage) {
  using C = MeshCaster<cast::Float>;
  const std::vector<double> v = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::uint32_t> f = {0, 1, 2};
  EXPECT_EQ(error_of([&] { C(VertexArray(static_cast<const double*>(nullptr), 3), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex array: null pointer with a count of 3");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3), IndexArray{nullptr, 1}); }),
            "MeshCaster: index array: null pointer with a count of 1");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3, 16), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex array: stride of 16 bytes is smaller than one element (24 bytes)");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3), IndexArray{f.data(), 1, 8}); }),
            "MeshCaster: index array: stride of 8 bytes is smaller than one element (12 bytes)");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), std::size_t(1) << 33), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex array: count 8589934592 exceeds the limit of 2^32 - 2");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3, std::size_t(1) << 62), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex array: stride of 4611686018427387904 bytes exceeds the limit of 65536");
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3), IndexArray{f.data(), 1, 65540}); }),
            "MeshCaster: index array: stride of 65540 bytes exceeds the limit of 65536");
  const std::vector<std::uint32_t> out_of_range = {0, 1, 2, 2, 1, 3};
  EXPECT_EQ(error_of([&] { C(VertexArray(v.data(), 3), IndexArray{out_of_range.data(), 2}); }),
            "MeshCaster: triangle 1 has vertex index 3 out of range (vertex count 3)");
  std::vector<double> nan_v = v;
  nan_v[4] = kNaN<double>;
  EXPECT_EQ(error_of([&] { C(VertexArray(nan_v.data(), 3), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex 1 (used by triangle 0) has a NaN or infinite coordinate");
  const std::vector<float> inf_v = {0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0};
  EXPECT_EQ(error_of([&] { C(VertexArray(inf_v.data(), 3), IndexArray{f.data(), 1}); }),
            "MeshCaster: vertex 2 (used by triangle 0) has a NaN or infinite coordinate");
  // An unused NaN vertex is not an error.
  std::vector<double> unused = v;
  unused.insert(unused.end(), {kNaN<double>, 0, 0});
  EXPECT_EQ(error_of([&] { C(VertexArray(unused.data(), 4), IndexArray{f.data(), 1}); }), "(no error)");
  // Batches: spans that disagree.
  const C c(VertexArray(v.data(), 3), IndexArray{f.data(), 1});
  const std::vector<Ray<double>> rays(3, Ray<double>{{0.2, 0.2, 1}, {0, 0, -1}});
  std::vector<MeshHit> two(2), three(3);
  const std::vector<TRange> ranges(2);
  EXPECT_EQ(error_of([&] { c.closest(rays, {}, two); }), "MeshCaster: 2 results for 3 rays");
  EXPECT_EQ(error_of([&] { c.closest(rays, ranges, three); }),
            "MeshCaster: 2 ranges for 3 rays (expected 0, 1 or one per ray)");
  std::vector<std::uint8_t> any(3);
  EXPECT_EQ(error_of([&] { c.any(rays, ranges, any); }), "MeshCaster: 2 ranges for 3 rays (expected 0, 1 or one per ray)");
}

TEST(MeshCaster, AllHitsAreSortedAndOneRangeServesEveryRay) {
  // Ten parallel unit squares (two triangles each) stacked along z, listed in a shuffled order.
  std::vector<float> v;
  std::vector<std::uint32_t> f;
  const int order[10] = {3, 7, 0, 9, 5, 1, 8, 2, 6, 4};
  for (int k = 0; k < 10; ++k) {
    const float z = float(order[k]);
    const auto b = std::uint32_t(v.size() / 3);
    v.insert(v.end(), {0, 0, z, 1, 0, z, 1, 1, z, 0, 1, z});
    f.insert(f.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  }
  const MeshCaster<cast::Robust> c(VertexArray(v.data(), v.size() / 3), IndexArray{f.data(), f.size() / 3});
  const Ray<double> r{{0.3, 0.6, -1}, {0, 0, 1}};
  const auto all = c.all(r);
  ASSERT_EQ(all.size(), 10u);
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].t, double(k + 1));
    EXPECT_EQ(all[k].contact, Contact::interior);
    if (k) {
      EXPECT_LT(all[k - 1].t, all[k].t);
    }
  }
  EXPECT_EQ(c.all(r, {2.5, 6}).size(), 4u);
  // One range for a whole batch: [4.5, inf) skips the squares at z = 0 .. 3 (t = 1 .. 4).
  const std::vector<Ray<double>> rays = {r, {{0.6, 0.3, -1}, {0, 0, 1}}};
  std::vector<MeshHit> out(2);
  const TRange from{4.5, kInf};
  c.closest(rays, {&from, 1}, out);
  for (const auto& h : out) EXPECT_EQ(h.t, 5.0);
  // Barycentrics: the hit point rebuilt from them is the ray's point.
  const MeshHit h = c.closest(r);
  ASSERT_TRUE(h.hit());
  const auto& tri = f;
  const auto at = [&](std::uint32_t i) {
    return Vec3<double>{v[3 * i], v[3 * i + 1], v[3 * i + 2]};
  };
  const Vec3<double> p0 = at(tri[3 * h.triangle]), p1 = at(tri[3 * h.triangle + 1]), p2 = at(tri[3 * h.triangle + 2]);
  const Vec3<double> p = (1 - h.b1 - h.b2) * p0 + h.b1 * p1 + h.b2 * p2;
  EXPECT_NEAR(p.x, 0.3, 1e-6);
  EXPECT_NEAR(p.y, 0.6, 1e-6);
  EXPECT_NEAR(p.z, 0.0, 1e-6);
}
