// ExactMesh (rayproof/scene/contains.h): exact containment on shapes whose inside is known in closed
// form (cube, dented cube, octahedron), on the lattice points whose rays pass through their edges
// and vertices, on their faces, edges and vertices and one ulp off them; open and misoriented meshes;
// a self-intersecting mesh; segments; the BVH against a brute-force count along another axis.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/orient.h"
#include "exact/orient_exact.h"

namespace {

using rayproof::ExactMesh;
using rayproof::Side;
using rayproof::Vec3;
using Tri = std::array<std::uint32_t, 3>;

struct Shape {
  std::vector<Vec3<double>> v;
  std::vector<Tri> t;
};

ExactMesh make(const Shape& s, rayproof::ContainsRule rule = rayproof::ContainsRule::automatic) {
  return ExactMesh({&s.v[0].x, s.v.size()}, {s.t.front().data(), s.t.size()}, rule);
}

/// [0, 2]^3, outward.
Shape cube() {
  Shape s;
  for (int i = 0; i < 8; ++i) s.v.push_back({double(2 * (i & 1)), double(i >> 1 & 1) * 2, double(i >> 2 & 1) * 2});
  s.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

/// The cube with its top face replaced by a pyramid down to (1, 1, 1): inside iff
/// 0 < x, y < 2 and 0 < z < 1 + max(|x - 1|, |y - 1|).
Shape dented_cube() {
  Shape s = cube();
  s.t.erase(s.t.begin() + 2, s.t.begin() + 4);  // the top face z = 2 (vertices 4 5 6 7)
  s.v.push_back({1, 1, 1});                      // vertex 8
  s.t.push_back({4, 5, 8}), s.t.push_back({5, 7, 8}), s.t.push_back({7, 6, 8}), s.t.push_back({6, 4, 8});
  return s;
}

/// |x| + |y| + |z| <= 1.
Shape octahedron() {
  Shape s;
  s.v = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) {
        // Outward: (x, y, z) counterclockwise seen from outside iff the octant's sign product is +.
        const bool flip = ((sx == 1) + (sy == 3) + (sz == 5)) % 2;
        s.t.push_back(flip ? Tri{std::uint32_t(sx), std::uint32_t(sz), std::uint32_t(sy)}
                           : Tri{std::uint32_t(sx), std::uint32_t(sy), std::uint32_t(sz)});
      }
  return s;
}

Side cube_truth(const Vec3<double>& p) {
  if (p.x < 0 || p.x > 2 || p.y < 0 || p.y > 2 || p.z < 0 || p.z > 2) return Side::outside;
  if (p.x == 0 || p.x == 2 || p.y == 0 || p.y == 2 || p.z == 0 || p.z == 2) return Side::surface;
  return Side::inside;
}
/// Exact for the lattice points used (multiples of 1/8 in [-1, 3]).
Side dented_truth(const Vec3<double>& p) {
  const double h = 1 + std::max(std::fabs(p.x - 1), std::fabs(p.y - 1));
  if (p.x < 0 || p.x > 2 || p.y < 0 || p.y > 2 || p.z < 0 || p.z > h) return Side::outside;
  if (p.x == 0 || p.x == 2 || p.y == 0 || p.y == 2 || p.z == 0 || p.z == h) return Side::surface;
  return Side::inside;
}
Side octa_truth(const Vec3<double>& p) {
  const double r = std::fabs(p.x) + std::fabs(p.y) + std::fabs(p.z);  // exact on the lattices used
  return r < 1 ? Side::inside : (r == 1 ? Side::surface : Side::outside);
}

template <class Truth>
int wrong_on_lattice(const ExactMesh& m, double lo, double hi, double step, Truth truth, int& surface) {
  int wrong = 0;
  for (double x = lo; x <= hi; x += step)
    for (double y = lo; y <= hi; y += step)
      for (double z = lo; z <= hi; z += step) {
        const Vec3<double> p{x, y, z};
        const Side got = m.contains(p), want = truth(p);
        surface += want == Side::surface;
        // The winding number too: a double count (2) would still be "inside" under the nonzero rule.
        const std::int32_t w = m.oriented() ? m.winding(p) : 0;
        const std::int32_t want_w = want == Side::inside ? 1 : (want == Side::surface ? ExactMesh::kOnSurface : 0);
        if (got != want || (m.oriented() && w != want_w)) {
          if (++wrong <= 5) ADD_FAILURE() << "(" << x << ", " << y << ", " << z << "): " << to_string(got) << ", want " << to_string(want)
                                 << " (winding " << w << ")";
        }
      }
  return wrong;
}

TEST(ExactMesh, LatticeOnCubeDentedCubeOctahedron) {
  // Step 1/8 (cube) and 1/16 (octahedron): the points on faces, edges and vertices, and the axis
  // rays through edges and vertices (every lattice line through a vertex or the diagonals).
  int surface = 0;
  EXPECT_EQ(wrong_on_lattice(make(cube()), -0.5, 2.5, 0.125, cube_truth, surface), 0);
  EXPECT_EQ(wrong_on_lattice(make(dented_cube()), -0.5, 2.5, 0.125, dented_truth, surface), 0);
  EXPECT_EQ(wrong_on_lattice(make(octahedron()), -1.25, 1.25, 0.0625, octa_truth, surface), 0);
  EXPECT_GT(surface, 3000);  // the lattices do put thousands of points on the surfaces
}

TEST(ExactMesh, OneUlpOffTheSurface) {
  const ExactMesh c = make(cube()), o = make(octahedron());
  int n = 0;
  for (double a = 0.125; a < 2; a += 0.25)
    for (double b = 0.125; b < 2; b += 0.25) {
      EXPECT_EQ(c.contains({std::nextafter(2.0, 3.0), a, b}), Side::outside);
      EXPECT_EQ(c.contains({std::nextafter(2.0, 0.0), a, b}), Side::inside);
      EXPECT_EQ(c.contains({a, b, std::nextafter(0.0, -1.0)}), Side::outside);  // the smallest subnormal
      EXPECT_EQ(c.contains({a, b, std::nextafter(0.0, 1.0)}), Side::inside);
      EXPECT_EQ(c.contains({a, b, 0.0}), Side::surface);
      ++n;
    }
  // Octahedron faces x + y + z = 1 at dyadic points, one coordinate nudged by an ulp either way.
  for (double x = 0.0625; x < 1; x += 0.0625)
    for (double y = 0.0625; x + y < 1; y += 0.0625) {
      const double z = 1 - x - y;
      EXPECT_EQ(o.contains({x, y, z}), Side::surface);
      EXPECT_EQ(o.contains({std::nextafter(x, 2.0), y, z}), Side::outside);
      EXPECT_EQ(o.contains({x, std::nextafter(y, 0.0), z}), Side::inside);
      EXPECT_EQ(o.contains({-x, -y, std::nextafter(-z, -2.0)}), Side::outside);
      EXPECT_EQ(o.contains({-x, y, std::nextafter(-z, 0.0)}), Side::inside);
      ++n;
    }
  EXPECT_GT(n, 150);
}

TEST(ExactMesh, WindingNumberAndOrientation) {
  const ExactMesh c = make(cube());
  EXPECT_TRUE(c.oriented());
  EXPECT_EQ(c.winding({1, 1, 1}), 1);
  EXPECT_EQ(c.winding({3, 1, 1}), 0);
  EXPECT_EQ(c.winding({2, 1, 1}), ExactMesh::kOnSurface);
  // Inward-facing triangles: winding -1, still inside.
  Shape inv = cube();
  for (Tri& t : inv.t) std::swap(t[1], t[2]);
  const ExactMesh ci = make(inv);
  EXPECT_EQ(ci.winding({1, 1, 1}), -1);
  EXPECT_EQ(ci.contains({1, 1, 1}), Side::inside);
  // A ray from the centre along +x through the face's diagonal (an edge of two triangles): once.
  EXPECT_EQ(c.crossings({1, 1, 1}), 1u);
  EXPECT_EQ(make(octahedron()).crossings({0, 0, 0}), 1u);  // every axis ray through a vertex
}

TEST(ExactMesh, InvalidPoints) {
  const ExactMesh c = make(cube());
  EXPECT_EQ(c.contains({std::nan(""), 1, 1}), Side::invalid);
  EXPECT_EQ(c.contains({1, INFINITY, 1}), Side::invalid);
  EXPECT_EQ(c.contains({1e308, -1e308, 1}), Side::outside);
}

TEST(ExactMesh, OpenMeshIsRefusedForNonzeroAndParityNamingAnEdge) {
  Shape s = cube();
  s.t.pop_back();
  EXPECT_EQ(make(s).rule(), rayproof::ContainsRule::winding);  // automatic: the generalized winding number
  EXPECT_THROW((void)make(s, rayproof::ContainsRule::parity), rayproof::MeshNotClosedError);
  try {
    (void)make(s, rayproof::ContainsRule::nonzero);
    FAIL() << "an open mesh was accepted for the nonzero rule";
  } catch (const rayproof::MeshNotClosedError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("not closed: 3 edges"), std::string::npos) << m;
    EXPECT_NE(m.find("vertex "), std::string::npos) << m;
  }
}

TEST(ExactMesh, DuplicatedVerticesAreWelded) {
  // Every triangle with its own three vertices (as STL stores them): closed after welding.
  const Shape c = cube();
  Shape soup;
  for (const Tri& t : c.t) {
    const auto n = std::uint32_t(soup.v.size());
    for (std::uint32_t k : t) soup.v.push_back(c.v[k]);
    soup.t.push_back({n, n + 1, n + 2});
  }
  const ExactMesh m = make(soup);
  EXPECT_EQ(m.contains({1, 1, 1}), Side::inside);
  EXPECT_EQ(m.contains({0, 1, 1}), Side::surface);
}

TEST(ExactMesh, MisorientedMeshUsesParityOrIsRefusedForNonzero) {
  Shape s = cube();
  std::swap(s.t[0][1], s.t[0][2]);  // one triangle flipped: closed, not oriented
  EXPECT_THROW((void)make(s, rayproof::ContainsRule::nonzero), rayproof::MeshNotClosedError);
  const ExactMesh m = make(s);
  EXPECT_FALSE(m.oriented());
  EXPECT_EQ(m.rule(), rayproof::ContainsRule::parity);
  EXPECT_THROW((void)m.winding({1, 1, 1}), std::logic_error);
  int surface = 0;
  EXPECT_EQ(wrong_on_lattice(m, -0.5, 2.5, 0.25, cube_truth, surface), 0);
}

TEST(ExactMesh, SelfIntersectingMeshHasItsWindingNumber) {
  // Two overlapping cubes as one mesh: winding 2 in the overlap. Nonzero: inside; parity: outside.
  Shape s = cube(), t = cube();
  for (auto& p : t.v) p = {p.x + 1, p.y, p.z};
  for (Tri tr : t.t) s.t.push_back({tr[0] + 8, tr[1] + 8, tr[2] + 8});
  s.v.insert(s.v.end(), t.v.begin(), t.v.end());
  const ExactMesh nz = make(s), par = make(s, rayproof::ContainsRule::parity);
  EXPECT_EQ(nz.winding({1.5, 1, 1}), 2);
  EXPECT_EQ(nz.winding({0.5, 1, 1}), 1);
  EXPECT_EQ(nz.contains({1.5, 1, 1}), Side::inside);
  EXPECT_EQ(par.contains({1.5, 1, 1}), Side::outside);
  EXPECT_EQ(par.contains({2.5, 1, 1}), Side::inside);
}

TEST(ExactMesh, Segments) {
  const ExactMesh c = make(cube());
  auto h = c.segment({-1, 1, 1}, {1, 1, 1});  // through the face x = 0 at its diagonal (an edge)
  EXPECT_TRUE(h.crosses);
  EXPECT_EQ(h.p_side, Side::outside);
  EXPECT_EQ(h.q_side, Side::inside);
  EXPECT_EQ(h.contact, rayproof::Contact::edge);
  EXPECT_DOUBLE_EQ(h.t, 0.5);
  h = c.segment({-1, 0.5, 0.25}, {3, 0.5, 0.25});  // in and out: first at x = 0
  EXPECT_TRUE(h.crosses);
  EXPECT_EQ(h.contact, rayproof::Contact::interior);
  EXPECT_DOUBLE_EQ(h.t, 0.25);
  h = c.segment({-1, -1, -1}, {-0.5, -0.5, -0.5});  // stops short of the vertex (0, 0, 0)
  EXPECT_FALSE(h.crosses);
  h = c.segment({-1, -1, -1}, {0, 0, 0});  // ends exactly on it
  EXPECT_TRUE(h.crosses);
  EXPECT_EQ(h.contact, rayproof::Contact::vertex);
  EXPECT_EQ(h.q_side, Side::surface);
  EXPECT_EQ(h.t, 1.0);
  h = c.segment({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5});  // inside throughout
  EXPECT_FALSE(h.crosses);
  h = c.segment({-1, 0, 1}, {3, 0, 1});  // along the face y = 0: coplanar
  EXPECT_TRUE(h.crosses);
  EXPECT_EQ(h.contact, rayproof::Contact::coplanar);
  EXPECT_DOUBLE_EQ(h.t, 0.25);
  // q - p not exact in double: the candidates from the boxes, the same answer.
  h = c.segment({-0.1, 0.3, 0.7}, {1.7, 0.3, 0.7});
  EXPECT_TRUE(h.crosses);
  EXPECT_NEAR(h.t, 0.1 / 1.8, 1e-15);
}

TEST(Orient, FilterAndExpansionsAgreeWithGmpOnNearDegenerateInputs) {
  // Points nearly on a plane / line (one coordinate nudged by a few ulps), at several scales, and
  // inputs spanning huge exponent ranges (the expansions' window left: GMP decides).
  namespace certified = rayproof::certified;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int zeros = 0;
  for (int i = 0; i < 4000; ++i) {
    const double scale = std::ldexp(1.0, int(rng() % 1200) - 600);
    const Vec3<double> a{u(rng) * scale, u(rng) * scale, u(rng) * scale}, b{u(rng) * scale, u(rng) * scale, u(rng) * scale};
    const double s = u(rng);
    Vec3<double> c{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), u(rng) * scale};
    Vec3<double> p{a.x + 0.5 * (b.x - a.x), a.y + 0.5 * (b.y - a.y), a.z + 0.5 * (b.z - a.z)};  // near the segment ab
    for (int k = 0; k < int(rng() % 3); ++k) p.z = std::nextafter(p.z, (rng() & 1) ? 1e300 : -1e300);
    if (i % 4 == 0) c = {std::ldexp(u(rng), -1000), std::ldexp(u(rng), 900), 0};  // a huge exponent spread
    const int o3 = rayproof::orient::orient3d(a, b, c, p), g3 = certified::orient3d_gmp(a, b, c, p);
    if (o3 != rayproof::orient::kUnknown) {
      EXPECT_EQ(o3, g3) << i;
    }
    EXPECT_EQ(certified::orient3d_exact(a, b, c, p), g3) << i;
    const int o2 = rayproof::orient::orient2d(a.x, a.y, b.x, b.y, c.x, c.y), g2 = certified::orient2d_gmp(a.x, a.y, b.x, b.y, c.x, c.y);
    if (o2 != rayproof::orient::kUnknown) {
      EXPECT_EQ(o2, g2) << i;
    }
    EXPECT_EQ(certified::orient2d_exact(a.x, a.y, b.x, b.y, c.x, c.y), g2) << i;
    zeros += g2 == 0;
  }
  // Exactly degenerate: collinear and coplanar points with exact coordinates.
  EXPECT_EQ(certified::orient3d_exact({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0x1p-1074, 0x1p600, 0}), 0);
  EXPECT_EQ(certified::orient3d_exact({0, 0, 0}, {0x1p600, 0, 0}, {0, 0x1p-600, 0}, {0, 0, 0x1p-1074}), 1);
  EXPECT_EQ(certified::orient2d_exact(0, 0, 0x1p-1074, 0x1p-1074, 0x1p1000, 0x1p1000), 0);
  (void)zeros;
}

TEST(Orient, GmpSignsAtEveryScale) {
  // The GMP stage works on the inputs as integers times one power of two: small integer points
  // scaled by powers of two down into the subnormals and up to 2^900 keep their sign (a positive
  // scale), and a point moved off the plane x = 0 by the least subnormal takes the sign of the
  // normal of the other three in x (orient3d(a, b, c, p) = 2^-1074 ((b - a) x (c - a)).x).
  namespace certified = rayproof::certified;
  std::mt19937_64 rng(17);
  auto small = [&] { return double(int(rng() % 31) - 15); };
  int zeros = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3<double> a{small(), small(), small()}, b{small(), small(), small()}, c{small(), small(), small()};
    Vec3<double> p{small(), small(), small()};
    if (i % 3 == 0) p = {a.x + b.x - c.x, a.y + b.y - c.y, a.z + b.z - c.z};  // coplanar
    const int r3 = rayproof::orient::orient3d_exact_differences(a, b, c, p);
    const int r2 = rayproof::orient::orient2d_exact_differences(a.x, a.y, b.x, b.y, p.x, p.y);
    ASSERT_NE(r3, rayproof::orient::kUnknown);
    zeros += r3 == 0;
    for (const int e : {-1070, -1060, -600, 0, 400, 900}) {
      auto s = [e](const Vec3<double>& v) { return Vec3<double>{std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e)}; };
      EXPECT_EQ(certified::orient3d_gmp(s(a), s(b), s(c), s(p)), r3) << i << " 2^" << e;
      EXPECT_EQ(certified::orient2d_gmp(s(a).x, s(a).y, s(b).x, s(b).y, s(p).x, s(p).y), r2) << i << " 2^" << e;
    }
    // a on x = 0, p = a moved by the least subnormal in x: the sign of (b - a) x (c - a) in x.
    const Vec3<double> a0{0, a.y + 0.3, a.z - 0.7};
    const Vec3<double> p0{0x1p-1074, a0.y, a0.z};
    const int nx = certified::orient2d_exact(a0.y, a0.z, b.y, b.z, c.y, c.z);
    EXPECT_EQ(certified::orient3d_gmp(a0, b, c, p0), nx) << i;
    EXPECT_EQ(certified::orient3d_exact(a0, b, c, p0), nx) << i;
  }
  EXPECT_GT(zeros, 900);
}

TEST(Orient, AxisAlignedZerosWithoutTheExactStage) {
  // Points on a common axis-aligned plane (or line) have exact-zero orient3d terms: decided 0 from
  // the zero differences, at any scale (subnormals too); moved off the plane by one ulp, not 0.
  namespace certified = rayproof::certified;
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  int zeros = 0;
  for (int i = 0; i < 4000; ++i) {
    const double scale = std::ldexp(1.0, int(rng() % 1400) - 1100);
    const int k = int(rng() % 3);
    const double level = i % 5 == 0 ? 0.0 : u(rng) * scale;
    auto on = [&] {
      Vec3<double> v{u(rng) * scale, u(rng) * scale, u(rng) * scale};
      v[k] = level;
      if (i % 7 == 0) v[(k + 1) % 3] = level;  // on a common axis-parallel line too
      return v;
    };
    const Vec3<double> a = on(), b = on(), c = on();
    Vec3<double> p = on();
    if (i % 3 == 1) p[k] = std::nextafter(p[k], (rng() & 1) ? 1e300 : -1e300);  // off the plane
    const int o3 = rayproof::orient::orient3d(a, b, c, p), g3 = certified::orient3d_gmp(a, b, c, p);
    if (i % 3 != 1) {
      EXPECT_EQ(o3, 0) << i;  // decided without the expansions, even outside their window
    }
    if (o3 != rayproof::orient::kUnknown) {
      EXPECT_EQ(o3, g3) << i;
    }
    EXPECT_EQ(certified::orient3d_exact(a, b, c, p), g3) << i;
    zeros += g3 == 0;
  }
  EXPECT_GT(zeros, 2000);
  // A NaN still leaves the filter undecided (the callers' checks see it).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(rayproof::orient::orient3d({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}), rayproof::orient::kUnknown);
}

TEST(Orient, ExactDifferencesStageAgreesWithGmp) {
  // Points of a common grid (exact differences) at many scales: exactly coplanar and collinear
  // ones, ones an ulp of the grid off, and random ones; the stack stage must decide each of them
  // and agree with GMP, and orient3d / orient2d through it too.
  namespace certified = rayproof::certified;
  using rayproof::orient::kUnknown;
  std::mt19937_64 rng(11);
  int decided3 = 0, decided2 = 0, zeros3 = 0, zeros2 = 0;
  for (int i = 0; i < 20000; ++i) {
    const int e = int(rng() % 400) - 200;
    const double step = std::ldexp(1.0, e);
    auto g = [&] { return double(std::int64_t(rng() % (std::uint64_t(1) << 31)) - (std::int64_t(1) << 30)) * step; };
    const Vec3<double> a{g(), g(), g()}, b{g(), g(), g()}, c{g(), g(), g()};
    Vec3<double> p{g(), g(), g()};
    if (i % 3 == 0) {  // exactly on the plane of a, b, c when the combination is exact
      const std::int64_t s = std::int64_t(rng() % 5) - 2, t = std::int64_t(rng() % 5) - 2;
      p = {a.x + s * (b.x - a.x) + t * (c.x - a.x), a.y + s * (b.y - a.y) + t * (c.y - a.y),
           a.z + s * (b.z - a.z) + t * (c.z - a.z)};
    }
    if (i % 6 == 1) p.z += step * (rng() & 1 ? 1 : -1) * 0x1p-30;  // off the grid: a difference may be inexact
    const int s3 = rayproof::orient::orient3d_exact_differences(a, b, c, p), g3 = certified::orient3d_gmp(a, b, c, p);
    if (s3 != kUnknown) {
      ++decided3;
      zeros3 += s3 == 0;
      EXPECT_EQ(s3, g3) << i;
    }
    EXPECT_EQ(certified::orient3d_exact(a, b, c, p), g3) << i;
    const Vec3<double> q = i % 2 ? p : Vec3<double>{a.x + 3 * (b.x - a.x), a.y + 3 * (b.y - a.y), 0};  // collinear
    const int s2 = rayproof::orient::orient2d_exact_differences(a.x, a.y, b.x, b.y, q.x, q.y),
              g2 = certified::orient2d_gmp(a.x, a.y, b.x, b.y, q.x, q.y);
    if (s2 != kUnknown) {
      ++decided2;
      zeros2 += s2 == 0;
      EXPECT_EQ(s2, g2) << i;
    }
    EXPECT_EQ(certified::orient2d_exact(a.x, a.y, b.x, b.y, q.x, q.y), g2) << i;
  }
  // Most cases are on the grid (the stage decides them), and many of them are exact zeros.
  EXPECT_GT(decided3, 15000);
  EXPECT_GT(decided2, 15000);
  EXPECT_GT(zeros3, 3000);
  EXPECT_GT(zeros2, 5000);
  // A difference that is not a double: the stage declines.
  EXPECT_EQ(rayproof::orient::orient2d_exact_differences(1, 0, 0x1p-60, 0, 3, 1), kUnknown);
}

/// The winding number of the perturbed ray along +z, over every triangle (no BVH): an independent count.
int brute_winding_z(const rayproof::mesh::Mesh& m, const Vec3<double>& p) {
  using rayproof::orient::orient2d;
  int w = 0;
  for (const auto& t : m.triangles) {
    const Vec3<double>&a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    // (k, u, v) = (z, x, y); p' = p + eps e_x + eps^2 e_y.
    auto e = [&](const Vec3<double>& s, const Vec3<double>& r) {
      const int o = orient2d(s.x, s.y, r.x, r.y, p.x, p.y);
      if (o != 0) return o;
      if (r.y != s.y) return s.y > r.y ? 1 : -1;
      return r.x > s.x ? 1 : -1;
    };
    const int sk = orient2d(a.x, a.y, b.x, b.y, c.x, c.y);
    if (sk == 0 || e(a, b) != sk || e(b, c) != sk || e(c, a) != sk) continue;
    if (rayproof::orient::orient3d(a, b, c, p) == -sk) w += sk;
  }
  return w;
}

TEST(ExactMesh, BunnyAgreesWithBruteForceAlongAnotherAxis) {
#ifndef RAYPROOF_CGAL_MESHES
  GTEST_SKIP() << "CGAL's demo meshes were not extracted (libcgal-dev's data.tar.gz missing)";
#else
  const std::string path = std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not extracted";
  const auto mesh = rayproof::mesh::read_mesh(path);
  const ExactMesh m({&mesh.vertices[0].x, mesh.vertices.size()}, {mesh.triangles.front().data(), mesh.triangles.size()});
  Vec3<double> lo = mesh.vertices[0], hi = lo;
  for (const auto& v : mesh.vertices)
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)}, hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0, 1);
  int inside = 0;
  for (int i = 0; i < 300; ++i) {
    // Random points, and vertices (surface) and edge midpoints' neighbours.
    Vec3<double> p{lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
    if (i % 3 == 1) p = mesh.vertices[rng() % mesh.vertices.size()];
    const Side got = m.contains(p);
    if (i % 3 == 1) {
      EXPECT_EQ(got, Side::surface);
      continue;
    }
    ASSERT_NE(got, Side::surface);
    const int w = brute_winding_z(mesh, p);
    EXPECT_EQ(m.winding(p), w) << i;
    inside += w != 0;
  }
  EXPECT_GT(inside, 10);
#endif
}

}  // namespace
