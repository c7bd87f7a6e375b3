// ExactMesh::closest_point (rayproof/scene/distance.h) against a brute force in GMP rationals on
// small meshes: every triangle's exact squared distance from its features (vertices, edge
// projections, face projection: another formulation than the library's), the nearest triangles
// (ties by symmetry), the distance checked by exact comparison with the squares of the midpoints
// to its neighbouring doubles; points on vertices, edges and faces, far points, the meshes and
// points scaled by 2^600 and 2^-600, random soups with zero-area triangles, invalid points.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rayproof/scene/distance.h"
#include "scene/distance_bounds.h"
#include "scene/distance_tree.h"

namespace {

using rayproof::ExactMesh;
using rayproof::ClosestPoint;
using rayproof::Side;
using rayproof::Vec3;
using Tri = std::array<std::uint32_t, 3>;
using Q = mpq_class;

struct Shape {
  std::vector<Vec3<double>> v;
  std::vector<Tri> t;
};

ExactMesh make(const Shape& s) { return ExactMesh({&s.v[0].x, s.v.size()}, {s.t.front().data(), s.t.size()}); }

Shape cube(double lo = 0, double hi = 2) {
  Shape s;
  for (int i = 0; i < 8; ++i) s.v.push_back({i & 1 ? hi : lo, i >> 1 & 1 ? hi : lo, i >> 2 & 1 ? hi : lo});
  s.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

Shape octahedron() {
  Shape s;
  s.v = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (std::uint32_t sx : {0u, 1u})
    for (std::uint32_t sy : {2u, 3u})
      for (std::uint32_t sz : {4u, 5u}) {
        const bool flip = (sx == 1) ^ (sy == 3) ^ (sz == 5);
        s.t.push_back(flip ? Tri{sx, sz, sy} : Tri{sx, sy, sz});
      }
  return s;
}

Shape scaled(Shape s, double f) {
  for (auto& v : s.v) v = {v.x * f, v.y * f, v.z * f};
  return s;
}

struct QV {
  Q x, y, z;
};
QV qv(const Vec3<double>& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
QV operator-(const QV& a, const QV& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
QV operator*(const Q& s, const QV& a) { return {s * a.x, s * a.y, s * a.z}; }
QV operator+(const QV& a, const QV& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Q dot(const QV& a, const QV& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
QV cross(const QV& a, const QV& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/// The exact squared distance from p to the closed triangle: the least over its vertices, the
/// projections on its edges that fall inside them and the projection on its plane when inside.
Q brute_triangle(const QV& p, const QV& a, const QV& b, const QV& c) {
  const QV v[3] = {a, b, c};
  Q best = dot(p - a, p - a);
  for (int k = 0; k < 3; ++k) {
    const QV& u = v[k];
    const QV& w = v[(k + 1) % 3];
    const Q du = dot(p - u, p - u);
    if (du < best) best = du;
    const QV d = w - u;
    const Q len = dot(d, d);
    if (len == 0) continue;
    const Q s = dot(d, p - u) / len;
    if (s > 0 && s < 1) {
      const QV e = p - (u + s * d);
      if (dot(e, e) < best) best = dot(e, e);
    }
  }
  const QV n = cross(b - a, c - a);
  const Q nn = dot(n, n);
  if (nn != 0) {
    const QV q = p - (dot(n, p - a) / nn) * n;  // the projection on the plane
    bool inside = true;
    for (int k = 0; k < 3; ++k)
      if (dot(n, cross(v[(k + 1) % 3] - v[k], q - v[k])) < 0) inside = false;
    if (inside) {
      const QV e = p - q;
      if (dot(e, e) < best) best = dot(e, e);
    }
  }
  return best;
}

struct Brute {
  Q d2;
  std::vector<std::uint32_t> nearest;  ///< every triangle at exactly d2
};
Brute brute(const Shape& s, const Vec3<double>& pd) {
  const QV p = qv(pd);
  Brute r;
  for (std::uint32_t i = 0; i < s.t.size(); ++i) {
    const Q d = brute_triangle(p, qv(s.v[s.t[i][0]]), qv(s.v[s.t[i][1]]), qv(s.v[s.t[i][2]]));
    if (r.nearest.empty() || d < r.d2) r.d2 = d, r.nearest = {i};
    else if (d == r.d2) r.nearest.push_back(i);
  }
  return r;
}

/// d is sqrt(d2) rounded to nearest, ties to even: exact comparisons with the midpoints' squares.
bool correctly_rounded(double d, const Q& d2) {
  if (!(d >= 0)) return false;
  if (d == 0) return d2 == 0 || d2 * 4 <= Q(std::numeric_limits<double>::denorm_min()) * std::numeric_limits<double>::denorm_min();
  const double inf = std::numeric_limits<double>::infinity();
  const bool even = (std::bit_cast<std::uint64_t>(d) & 1u) == 0;
  const Q up = std::isinf(std::nextafter(d, inf)) ? Q(1) << 1024 : Q(std::nextafter(d, inf));
  const Q mu = (Q(d) + up) / 2, md = (Q(d) + Q(std::nextafter(d, 0.0))) / 2;
  const int cu = cmp(d2, mu * mu), cd = cmp(d2, md * md);
  return (cu < 0 || (cu == 0 && even)) && (cd > 0 || (cd == 0 && even));
}

/// Checks one query against the brute force; returns the stage for tallies.
void check(const Shape& s, const ExactMesh& m, const Vec3<double>& p, const char* what) {
  SCOPED_TRACE(::testing::Message() << what << " p = (" << p.x << ", " << p.y << ", " << p.z << ")");
  const Brute b = brute(s, p);
  const ClosestPoint r = m.closest_point(p);
  ASSERT_FALSE(b.nearest.empty());
  EXPECT_EQ(r.triangle, b.nearest.front()) << "nearest (lowest of " << b.nearest.size() << " tied)";
  EXPECT_TRUE(correctly_rounded(r.distance, b.d2)) << "distance " << r.distance << " exact^2 " << b.d2.get_d();
  EXPECT_EQ(r.side, b.d2 == 0 ? Side::surface : m.contains(p));
  EXPECT_EQ(m.distance(p), r.distance);
  if (r.triangle < s.t.size()) {  // the closest point and barycentrics: on the triangle, near p's distance
    const auto& t = s.t[r.triangle];
    // The weights are ill-conditioned on slivers: checked on triangles with some area.
    const Vec3<double> e1 = s.v[t[1]] - s.v[t[0]], e2 = s.v[t[2]] - s.v[t[0]];
    const bool fat = rayproof::length(rayproof::cross(e1, e2)) > 1e-3 * std::max(rayproof::dot(e1, e1), rayproof::dot(e2, e2));
    const double sum = r.barycentric[0] + r.barycentric[1] + r.barycentric[2];
    EXPECT_NEAR(sum, 1.0, 1e-12);
    for (double w : r.barycentric) EXPECT_GE(w, -1e-12);
    const Vec3<double> q = r.point;
    Vec3<double> qb{0, 0, 0};
    for (int k = 0; k < 3; ++k) qb = qb + s.v[t[k]] * r.barycentric[k];
    const double scale = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z), std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    // Lengths with the scale divided out (no overflow near 2^1000).
    const double f = scale > 0 ? std::exp2(-std::ilogb(scale)) : 1.0;
    if (fat) EXPECT_NEAR(rayproof::length((qb - q) * f), 0.0, 1e-12 * scale * f);
    EXPECT_NEAR(rayproof::length((p - q) * f), r.distance * f, 1e-12 * std::max(scale, r.distance) * f)
        << "stage " << rayproof::to_string(r.stage) << " weights " << r.barycentric[0] << " " << r.barycentric[1] << " " << r.barycentric[2];
  }
}

TEST(Distance, CubeFacesEdgesVerticesAndOnTheSurface) {
  const Shape s = cube();
  const ExactMesh m = make(s);
  // Vertices, edge midpoints, face points with dyadic barycentrics: distance 0, surface.
  for (const auto& v : s.v) check(s, m, v, "vertex");
  for (const auto& t : s.t)
    for (int k = 0; k < 3; ++k) {
      const Vec3<double> a = s.v[t[k]], b = s.v[t[(k + 1) % 3]];
      check(s, m, (a + b) * 0.5, "edge midpoint");
      check(s, m, a * 0.25 + b * 0.75, "edge point");
    }
  for (const auto& t : s.t) check(s, m, s.v[t[0]] * 0.25 + s.v[t[1]] * 0.25 + s.v[t[2]] * 0.5, "face point");
  // Outside in the regions of the faces, edges and vertices; inside.
  for (double x : {-1.5, -0.25, 0.0, 0.5, 1.0, 1.75, 2.0, 3.0})
    for (double y : {-0.75, 0.0, 1.0, 1.25, 2.0, 2.5})
      for (double z : {-2.0, 0.0, 0.3, 1.0, 2.0, 2.1}) check(s, m, {x, y, z}, "lattice");
  EXPECT_EQ(m.closest_point({1, 1, 1}).side, Side::inside);
  EXPECT_EQ(m.closest_point({1, 1, 1}).distance, 1.0);
  EXPECT_EQ(m.signed_distance({1, 1, 1}), -1.0);
  EXPECT_EQ(m.signed_distance({1, 1, 3}), 1.0);
  EXPECT_EQ(m.signed_distance({1, 1, 2}), 0.0);
}

TEST(Distance, TiesBySymmetry) {
  // The centre of the cube is 1 from all twelve triangles; the octahedron's centre from all eight;
  // points on the axes are tied between the faces around a vertex.
  for (const Shape& s : {cube(), octahedron(), cube(-1, 1)}) {
    const ExactMesh m = make(s);
    for (const Vec3<double>& p : std::vector<Vec3<double>>{{1, 1, 1}, {0, 0, 0}, {0, 0, 3}, {0, 5, 0}, {-7, 0, 0}, {1, 1, 9},
                                                           {3, 3, 3}, {0.5, 0.5, 0.5}, {-2, -2, 0}})
      check(s, m, p, "symmetric");
  }
}

TEST(Distance, RandomPointsUniformAndNearTheSurface) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 2.5), tiny(-1e-9, 1e-9), w(0, 1);
  for (const Shape& s : {cube(), octahedron(), scaled(octahedron(), 3.3)}) {
    const ExactMesh m = make(s);
    for (int i = 0; i < 300; ++i) check(s, m, {u(rng), u(rng), u(rng)}, "uniform");
    for (int i = 0; i < 300; ++i) {  // a point of a random triangle, moved by about 1e-9
      const auto& t = s.t[rng() % s.t.size()];
      double a = w(rng), b = w(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec3<double> q = s.v[t[0]] * (1 - a - b) + s.v[t[1]] * a + s.v[t[2]] * b;
      check(s, m, {q.x + tiny(rng), q.y + tiny(rng), q.z + tiny(rng)}, "near");
      check(s, m, q, "on (rounded)");
    }
  }
}

TEST(Distance, FarPoints) {
  const Shape s = octahedron();
  const ExactMesh m = make(s);
  for (double f : {1e3, 1e15, 1e30, 1e100, 1e150, 1e200, 1e300})
    for (const Vec3<double>& d : std::vector<Vec3<double>>{{1, 0, 0}, {0.3, -0.7, 0.1}, {-1, -1, -1}, {0, 0, 1}})
      check(s, m, d * f, "far");
  // Farther than the double range: +inf.
  const Shape big = scaled(cube(-1, 1), 1.5e308);
  const ExactMesh mb = make(big);
  // The exact distance from (-1.7e308, ...) is sqrt(3) * 2e307 (representable); from (1.7e308, 1.7e308,
  // -1.7e308) to the opposite corner's octant much more than the largest double.
  EXPECT_TRUE(correctly_rounded(mb.distance({-1.7e308, -1.7e308, -1.7e308}), brute(big, {-1.7e308, -1.7e308, -1.7e308}).d2));
  const Shape far = scaled(cube(-1, 1), 1e308);
  const ExactMesh mf = make(far);
  EXPECT_TRUE(std::isinf(mf.distance({-1.7e308, -1.7e308, -1.7e308}) * 0 + mf.distance({1.7e308, 1.7e308, 1.7e308})) ||
              correctly_rounded(mf.distance({1.7e308, 1.7e308, 1.7e308}), brute(far, {1.7e308, 1.7e308, 1.7e308}).d2));
  check(big, mb, {1.7e308, 0, 0}, "near the top of the range");
}

TEST(Distance, ScaledByTwoToThePlusMinus600) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.5, 2.5);
  for (double f : {0x1p600, 0x1p-600, 0x1p-1000, 0x1p900}) {
    const Shape s0 = cube(), s = scaled(s0, f);
    const ExactMesh m0 = make(s0), m = make(s);
    for (int i = 0; i < 40; ++i) {
      const Vec3<double> p0{u(rng), u(rng), u(rng)}, p = p0 * f;
      check(s, m, p, "scaled");
      if (f >= 0x1p-600) EXPECT_EQ(m.distance(p), m0.distance(p0) * f);  // exact scaling, no subnormals
    }
    check(s, m, Vec3<double>{1, 1, 1} * f, "scaled centre");
    check(s, m, s.v[3], "scaled vertex");
    // A coordinate the scaling would make subnormal: the exact search instead of the scaled tree.
    if (f > 1) check(s, m, {0x1p-1000, f * 1.5, f * 3}, "unscalable point");
  }
}

TEST(Distance, RandomSoupsWithZeroAreaTriangles) {
  std::mt19937_64 rng(23);
  std::uniform_int_distribution<int> g(-4, 4);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int mesh = 0; mesh < 30; ++mesh) {
    Shape s;
    for (int i = 0; i < 12; ++i) s.v.push_back({double(g(rng)), double(g(rng)), double(g(rng)) * 0.5});
    for (int i = 0; i < 16; ++i) s.t.push_back({std::uint32_t(rng() % 12), std::uint32_t(rng() % 12), std::uint32_t(rng() % 12)});
    s.v.push_back({0, 0, 0}), s.v.push_back({1, 1, 1}), s.v.push_back({2, 2, 2});  // collinear: zero area
    s.t.push_back({12, 13, 14});
    const ExactMesh m = make(s);
    for (int i = 0; i < 40; ++i) check(s, m, {u(rng), u(rng), u(rng)}, "soup");
    for (int i = 0; i < 20; ++i) check(s, m, {double(g(rng)), double(g(rng)), double(g(rng)) * 0.5}, "soup lattice");
  }
}

TEST(Distance, InvalidPointsAndBatch) {
  const Shape s = cube();
  const ExactMesh m = make(s);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const Vec3<double>& p : std::vector<Vec3<double>>{{nan, 0, 0}, {0, inf, 0}, {0, 0, -inf}}) {
    const ClosestPoint r = m.closest_point(p);
    EXPECT_TRUE(std::isnan(r.distance));
    EXPECT_EQ(r.triangle, ClosestPoint::kNoTriangle);
    EXPECT_EQ(r.side, Side::invalid);
    EXPECT_TRUE(std::isnan(m.signed_distance(p)));
  }
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 3);
  std::vector<Vec3<double>> pts(5000);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
  pts[17] = {nan, 1, 1};
  std::vector<ClosestPoint> out(pts.size());
  m.closest_points(pts, out, true, 2);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const ClosestPoint r = m.closest_point(pts[i]);
    ASSERT_EQ(out[i].triangle, r.triangle);
    ASSERT_TRUE(out[i].distance == r.distance || (std::isnan(r.distance) && std::isnan(out[i].distance)));
    ASSERT_EQ(out[i].side, r.side);
  }
  std::vector<ClosestPoint> short_out(3);
  EXPECT_THROW(m.closest_points(pts, short_out), rayproof::MeshInputError);
}

TEST(Distance, RoundingTiesToEvenAndDuplicateTriangles) {
  // p - a = (1 + k 2^-53, 0, 0) exactly: the distance is a midpoint between doubles for odd k.
  for (double k : {1.0, 3.0, 5.0, 2.0}) {
    Shape s;
    s.v = {{-k * 0x1p-53, 0, 0}, {-1, 1, 0.5}, {-1, -1, -0.5}};
    s.t = {{0, 1, 2}};
    const ExactMesh m = make(s);
    check(s, m, {1, 0, 0}, "midpoint");
    const double want = k == 1 ? 1.0 : k == 3 ? 1 + 0x1p-51 : k == 5 ? 1 + 0x1p-51 : 1 + 0x1p-52;
    EXPECT_EQ(m.distance({1, 0, 0}), want) << k;
  }
  // The same triangle twice and a coplanar overlapping one: exact ties across different faces.
  Shape s;
  s.v = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 1, 0}, {3, -1, 0}, {-1, 3, 0}};
  s.t = {{3, 4, 5}, {0, 1, 2}, {6, 7, 8}};
  const ExactMesh m = make(s);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1, 5);
  for (int i = 0; i < 200; ++i) check(s, m, {u(rng), u(rng), u(rng)}, "duplicates");
  for (double z : {0.0, 0.25, -3.0}) check(s, m, {1, 1, z}, "duplicates");
}

TEST(Distance, SliversAndNearlyCollinearTriangles) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-2, 2), tiny(-1e-12, 1e-12);
  for (int mesh = 0; mesh < 20; ++mesh) {
    Shape s;
    for (int i = 0; i < 6; ++i) {
      const Vec3<double> a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
      const double t = std::uniform_real_distribution<double>(0, 1)(rng);
      const auto base = std::uint32_t(s.v.size());
      s.v.push_back(a), s.v.push_back(b);
      s.v.push_back({a.x + t * (b.x - a.x) + tiny(rng), a.y + t * (b.y - a.y) + tiny(rng), a.z + t * (b.z - a.z)});
      s.t.push_back({base, base + 1, base + 2});
    }
    const ExactMesh m = make(s);
    for (int i = 0; i < 50; ++i) check(s, m, {u(rng), u(rng), u(rng)}, "sliver");
    for (const auto& v : s.v) check(s, m, {v.x + tiny(rng), v.y, v.z}, "sliver vertex");
  }
}

TEST(Distance, PublicExactHelpers) {
  const std::array<Vec3<double>, 3> t{Vec3<double>{0, 0, 0}, {2, 0, 0}, {0, 2, 0}}, u{Vec3<double>{0, 0, 1}, {2, 0, 1}, {0, 2, 1}};
  EXPECT_EQ(rayproof::exact_triangle_distance({1, 1, 3}, t), 3.0);
  EXPECT_EQ(rayproof::exact_triangle_distance({3, 3, 0}, t), std::sqrt(8.0));
  EXPECT_EQ(rayproof::compare_triangle_distances({1, 1, 3}, t, u), 1);
  EXPECT_EQ(rayproof::compare_triangle_distances({1, 1, -3}, t, u), -1);
  EXPECT_EQ(rayproof::compare_triangle_distances({1, 1, 0.5}, t, u), 0);
  EXPECT_TRUE(std::isnan(rayproof::exact_triangle_distance({std::nan(""), 0, 0}, t)));
}

}  // namespace

// The batch (Morton order, each query seeded by the previous answer) must give contains(p)'s side
// and the single query's distance, on nested, overlapping and inverted shells (winding numbers 0,
// 1, 2, 3 and -1), with points on the surface and in runs that jump between components, on one
// and on two threads.
TEST(Distance, BatchSideIsContainsOnNestedOverlappingAndInvertedShells) {
  Shape s;
  auto add = [&](const Shape& c, bool invert) {
    const auto base = std::uint32_t(s.v.size());
    s.v.insert(s.v.end(), c.v.begin(), c.v.end());
    for (Tri t : c.t) s.t.push_back(invert ? Tri{t[0] + base, t[2] + base, t[1] + base} : Tri{t[0] + base, t[1] + base, t[2] + base});
  };
  add(cube(0, 2), false), add(cube(1, 3), false), add(cube(-1, 4), false), add(cube(6, 7), true);
  const ExactMesh m = make(s);
  ASSERT_EQ(m.rule(), rayproof::ContainsRule::nonzero);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2, 8);
  std::uniform_int_distribution<int> g(-4, 16);
  std::vector<Vec3<double>> pts(6000);
  for (std::size_t i = 0; i < pts.size(); ++i)
    pts[i] = i % 3 == 0 ? Vec3<double>{g(rng) * 0.5, g(rng) * 0.5, g(rng) * 0.5} : Vec3<double>{u(rng), u(rng), u(rng)};
  std::size_t inside = 0, surface = 0;
  for (int threads : {1, 2}) {
    std::vector<ClosestPoint> out(pts.size());
    m.closest_points(pts, out, true, threads);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Side want = out[i].distance == 0 ? Side::surface : m.contains(pts[i]);
      ASSERT_EQ(out[i].side, want) << "p = (" << pts[i].x << ", " << pts[i].y << ", " << pts[i].z << "), threads " << threads;
      ASSERT_EQ(out[i].distance, m.distance(pts[i]));
      inside += want == Side::inside, surface += want == Side::surface;
    }
  }
  EXPECT_GT(inside, 1000u);  // the sets reach the shells' insides and surfaces
  EXPECT_GT(surface, 100u);
}

// The wide first pass's leaf lanes (distance_bounds.h: box_bounds4, upper_bounds4) give each
// triangle's box bound, upper bound and direction bit for bit as the scalar functions, whose
// proofs they rely on: random, degenerate (repeated and collinear vertices), sliver and scaled
// triangles, points on their vertices, edges and faces and around them.
TEST(Distance, LeafLanesEqualTheScalarBoundsBitForBit) {
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "no AVX2";
  namespace d = rayproof::scene::detail;
  using T3 = std::array<Vec3<double>, 3>;
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  auto rv = [&](double sc) { return Vec3<double>{u(rng) * sc, u(rng) * sc, u(rng) * sc}; };
  std::size_t regions[3] = {0, 0, 0};  // interior, edge or vertex of the scalar's weights, roughly
  for (int round = 0; round < 40000; ++round) {
    const double sc = std::ldexp(1.0, int(rng() % 7) * 100 - 300);
    T3 tris[4];
    for (T3& t : tris) {
      t = {rv(sc), rv(sc), rv(sc)};
      switch (rng() % 6) {
        case 0: t[2] = t[1]; break;                                                  // repeated vertex
        case 1: t[2] = t[0] + (t[1] - t[0]) * 0.5; break;                            // collinear
        case 2: t[2] = t[0] + (t[1] - t[0]) * 0.25 + Vec3<double>{0, 0, sc * 1e-12}; break;  // sliver
        case 3: t[1] = t[0]; t[2] = t[0]; break;                                     // a point
        default: break;
      }
    }
    const T3& near = tris[rng() % 4];
    Vec3<double> p;
    switch (rng() % 5) {
      case 0: p = near[rng() % 3]; break;
      case 1: p = near[0] + (near[1] - near[0]) * 0.375; break;
      case 2: p = near[0] + (near[1] - near[0]) * 0.25 + (near[2] - near[0]) * 0.25; break;
      case 3: p = near[0] + rv(sc * 1e-9); break;
      default: p = rv(sc * 4); break;
    }
    const T3* g[4] = {&tris[0], &tris[1], &tris[2], &tris[3]};
    __m256d v[3][3];
    d::Lanes4 b;
    d::box_bounds4(g, p, v, b);
    d::upper_bounds4(v, p, b);
    for (int i = 0; i < 4; ++i) {
      Vec3<double> dir;
      const double box = d::triangle_box_lb(tris[i], p), ub = d::upper_bound(tris[i], p, &dir);
      ASSERT_EQ(b.box[i], box) << "round " << round << " lane " << i;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(b.ub[i]), std::bit_cast<std::uint64_t>(ub)) << "round " << round << " lane " << i;
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(std::bit_cast<std::uint64_t>(b.dir[k][i]), std::bit_cast<std::uint64_t>(dir[k])) << "round " << round;
      regions[std::min(2, int(dir[0] == 0) + int(dir[1] == 0) + int(dir[2] == 0))]++;
    }
  }
  EXPECT_GT(regions[0], 1000u);
}

// The same answers with the leaf lanes and without (the bench's ablation switch), on a bumpy
// closed mesh at uniform and near-surface points.
TEST(Distance, LeafLanesChangeNoAnswer) {
  Shape s = cube(0, 2);
  const ExactMesh m = make(s);
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1, 3);
  std::vector<Vec3<double>> pts(4000);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng)};
  for (std::size_t i = 0; i < pts.size(); i += 2) pts[i].x = std::nextafter(2.0, i % 4 ? 3.0 : 0.0);
  std::vector<ClosestPoint> a(pts.size()), b(pts.size());
  m.closest_points(pts, a, false, 1);
  rayproof::scene::detail::set_distance_ablation(rayproof::scene::detail::kAblateLanes);
  m.closest_points(pts, b, false, 1);
  rayproof::scene::detail::set_distance_ablation(rayproof::scene::detail::kAblateNone);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    ASSERT_EQ(a[i].distance, b[i].distance) << i;
    ASSERT_EQ(a[i].triangle, b[i].triangle) << i;
  }
}
