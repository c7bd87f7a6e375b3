// ExactMesh::ray_crossings (rayproof/scene/contains.h): every crossing of a ray once, with its
// direction, touches apart. Rays through a cube's faces, edges, face diagonals and vertices, along
// its faces and grazing its silhouette; a tetrahedron through and along its edges; an open box; and
// random rays on lattice meshes (closed, bumpy, holed) against a brute force in GMP rationals that
// moves the ray by an explicit small offset instead of the symbolic one, and against the exact
// winding number at the origin.
#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "rayproof/scene/exact_mesh.h"

namespace {

using rayproof::ExactMesh;
using rayproof::Contact;
using rayproof::CrossingDirection;
using rayproof::Ray;
using rayproof::RayCrossings;
using rayproof::Vec3;
using Tri = std::array<std::uint32_t, 3>;
constexpr auto In = CrossingDirection::in;
constexpr auto Out = CrossingDirection::out;

struct Shape {
  std::vector<Vec3<double>> v;
  std::vector<Tri> t;
};

ExactMesh make(const Shape& s) { return ExactMesh({&s.v[0].x, s.v.size()}, {s.t.front().data(), s.t.size()}); }

/// [0, 2]^3, outward; vertex i = 2 (i & 1, i >> 1 & 1, i >> 2 & 1).
Shape cube() {
  Shape s;
  for (int i = 0; i < 8; ++i) s.v.push_back({double(2 * (i & 1)), double(i >> 1 & 1) * 2, double(i >> 2 & 1) * 2});
  s.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return s;
}

/// The unit corner tetrahedron, outward.
Shape tetrahedron() {
  Shape s;
  s.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return s;
}

Ray<double> ray(Vec3<double> o, Vec3<double> d) { return {o, d}; }

std::vector<CrossingDirection> dirs(const RayCrossings& r) {
  std::vector<CrossingDirection> out;
  for (const auto& c : r.crossings) out.push_back(c.direction);
  return out;
}
std::vector<double> ts(const RayCrossings& r) {
  std::vector<double> out;
  for (const auto& c : r.crossings) out.push_back(c.t);
  return out;
}
std::size_t touches_of(const RayCrossings& r, Contact c) {
  std::size_t n = 0;
  for (const auto& t : r.touches) n += t.contact == c;
  return n;
}

TEST(Crossings, CubeThroughFaces) {
  const ExactMesh m = make(cube());
  const RayCrossings r = m.ray_crossings(ray({-1, 0.5, 0.75}, {1, 0, 0}));
  ASSERT_TRUE(r.valid);
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 3.0}));
  EXPECT_TRUE(r.touches.empty());
  EXPECT_EQ(r.net(), 0);
  // The face x = 0 is triangles 8 and 9, x = 2 is 10 and 11.
  EXPECT_TRUE(r.crossings[0].triangle == 8 || r.crossings[0].triangle == 9);
  EXPECT_TRUE(r.crossings[1].triangle == 10 || r.crossings[1].triangle == 11);
}

TEST(Crossings, CubeThroughEdgesDiagonalsAndVertices) {
  const ExactMesh m = make(cube());
  // Through the vertical edges x = y = 0 and x = y = 2 (each shared by two faces' triangles).
  RayCrossings r = m.ray_crossings(ray({-1, -1, 0.5}, {1, 1, 0}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 3.0}));
  EXPECT_TRUE(r.touches.empty());
  // Through the diagonals of the bottom and top faces (edges shared by coplanar triangles).
  r = m.ray_crossings(ray({1, 1, -1}, {0, 0, 1}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 3.0}));
  EXPECT_TRUE(r.touches.empty());
  // Through the opposite corners (0, 0, 0) and (2, 2, 2): six triangles meet at each.
  r = m.ray_crossings(ray({-1, -1, -1}, {1, 1, 1}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 3.0}));
  EXPECT_TRUE(r.touches.empty());
  // Through a corner out of the other side's face interior.
  r = m.ray_crossings(ray({-2, -1, -1}, {2, 1, 1}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 2.0}));
}

TEST(Crossings, CubeGrazingSilhouette) {
  const ExactMesh m = make(cube());
  // Touches the edge x = 0, z = 2 at (0, 1, 2) and leaves above the cube.
  RayCrossings r = m.ray_crossings(ray({-1, 1, 1}, {1, 0, 1}));
  EXPECT_TRUE(r.crossings.empty());
  ASSERT_EQ(r.touches.size(), 1u);
  EXPECT_EQ(r.touches[0].contact, Contact::edge);
  EXPECT_EQ(r.touches[0].t, 1.0);
  // Touches the corner (0, 0, 0) only.
  r = m.ray_crossings(ray({-1, -1, 1}, {1, 1, -1}));
  EXPECT_TRUE(r.crossings.empty());
  ASSERT_EQ(r.touches.size(), 1u);
  EXPECT_EQ(r.touches[0].contact, Contact::vertex);
  EXPECT_EQ(r.touches[0].t, 1.0);
  // A miss is neither.
  r = m.ray_crossings(ray({-1, -1, 1}, {1, 0, 0}));
  EXPECT_TRUE(r.crossings.empty() && r.touches.empty());
}

TEST(Crossings, CubeAlongFaces) {
  const ExactMesh m = make(cube());
  // In the plane of the top face: its two triangles are coplanar touches; the perturbed ray
  // (moved by eps^3 towards +z) passes above the cube, so the side faces are touched, not crossed.
  RayCrossings r = m.ray_crossings(ray({-1, 1, 2}, {1, 0, 0}));
  EXPECT_TRUE(r.crossings.empty());
  EXPECT_EQ(touches_of(r, Contact::coplanar), 2u);
  EXPECT_EQ(touches_of(r, Contact::edge), 2u);
  for (const auto& t : r.touches) {
    if (t.contact == Contact::coplanar) {
      EXPECT_TRUE(t.triangle == 2 || t.triangle == 3);
    }
  }
  // In the plane of the bottom face the perturbed ray runs just inside: in at x = 0, out at x = 2.
  r = m.ray_crossings(ray({-1, 1, 0}, {1, 0, 0}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 3.0}));
  EXPECT_EQ(touches_of(r, Contact::coplanar), 2u);
}

TEST(Crossings, OriginsInsideAndOnTheSurfaceAndRanges) {
  const ExactMesh m = make(cube());
  RayCrossings r = m.ray_crossings(ray({1, 1, 1}, {1, 0.25, 0.5}));
  EXPECT_EQ(dirs(r), (std::vector{Out}));
  EXPECT_EQ(r.net(), -m.winding({1, 1, 1}));
  // On the face x = 0: the contact at t = 0 counts (the range is closed).
  r = m.ray_crossings(ray({0, 1, 1}, {1, 0, 0}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{0.0, 2.0}));
  r = m.ray_crossings(ray({0, 1, 1}, {1, 0, 0}), {0.5, 10});
  EXPECT_EQ(dirs(r), (std::vector{Out}));
  r = m.ray_crossings(ray({-1, 1, 1}, {1, 0, 0}), {0, 1});
  EXPECT_EQ(dirs(r), (std::vector{In}));
  r = m.ray_crossings(ray({-1, 1, 1}, {1, 0, 0}), {0, 0.5});
  EXPECT_TRUE(r.valid && r.crossings.empty());
  // A range reaching behind the origin: the contacts at t < 0 count too (a face; two corners).
  r = m.ray_crossings(ray({1, 1, 1}, {1, 0.25, 0.5}), {-INFINITY, INFINITY});
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{-1.0, 1.0}));
  r = m.ray_crossings(ray({1, 1, 1}, {1, 1, 1}), {-5, 5});
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{-1.0, 1.0}));
  // Bad rays: not valid, nothing found.
  const double nan = std::nan("");
  EXPECT_FALSE(m.ray_crossings(ray({0, 0, 0}, {0, 0, 0})).valid);
  EXPECT_FALSE(m.ray_crossings(ray({nan, 0, 0}, {1, 0, 0})).valid);
  EXPECT_FALSE(m.ray_crossings(ray({0, 0, 0}, {1, 0, INFINITY})).valid);
}

TEST(Crossings, Tetrahedron) {
  const ExactMesh m = make(tetrahedron());
  // Through the slanted face's interior, out through the corner where three faces meet.
  RayCrossings r = m.ray_crossings(ray({1, 1, 1}, {-1, -1, -1}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  ASSERT_EQ(r.crossings.size(), 2u);
  EXPECT_NEAR(r.crossings[0].t, 2.0 / 3.0, 1e-15);
  EXPECT_EQ(r.crossings[0].triangle, 3u);
  EXPECT_EQ(r.crossings[1].t, 1.0);
  // Down the edge x = y = 0: faces x = 0 and y = 0 hold the ray (coplanar touches); the perturbed
  // ray (x = eps, y = eps^2) runs inside, in through the top vertex and out through the bottom one.
  r = m.ray_crossings(ray({0, 0, 2}, {0, 0, -1}));
  EXPECT_EQ(dirs(r), (std::vector{In, Out}));
  EXPECT_EQ(ts(r), (std::vector{1.0, 2.0}));
  EXPECT_EQ(touches_of(r, Contact::coplanar), 2u);
  // Mirrored in x = 0: x = eps is outside, so two vertex touches.
  const Shape t = tetrahedron();
  Shape mirrored = t;
  for (auto& p : mirrored.v) p.x = -p.x;
  for (auto& tri : mirrored.t) std::swap(tri[1], tri[2]);
  r = make(mirrored).ray_crossings(ray({0, 0, 2}, {0, 0, -1}));
  EXPECT_TRUE(r.crossings.empty());
  EXPECT_EQ(touches_of(r, Contact::vertex), 2u);
}

TEST(Crossings, OpenBox) {
  Shape s = cube();
  s.t.erase(s.t.begin() + 2, s.t.begin() + 4);  // no top face
  const ExactMesh m = make(s);
  EXPECT_FALSE(m.closed());
  // Down through the missing top: only the bottom, crossed along its normal (-z): out.
  RayCrossings r = m.ray_crossings(ray({0.5, 0.75, 3}, {0, 0, -1}));
  EXPECT_EQ(dirs(r), (std::vector{Out}));
  EXPECT_EQ(ts(r), (std::vector{3.0}));
  // Up through the bottom: in, and nothing at the top.
  r = m.ray_crossings(ray({0.5, 0.75, -1}, {0, 0, 1}));
  EXPECT_EQ(dirs(r), (std::vector{In}));
}

// ---- Brute force: every triangle in GMP rationals, the ray moved by an explicit offset.

struct Q3 {
  mpq_class x, y, z;
};
Q3 q3(const Vec3<double>& p) { return {p.x, p.y, p.z}; }
Q3 operator-(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 operator+(const Q3& a, const Q3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Q3 cross(const Q3& a, const Q3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
mpq_class dot(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
int sgn(const mpq_class& x) { return mpq_sgn(x.get_mpq_t()) > 0 ? 1 : (mpq_sgn(x.get_mpq_t()) < 0 ? -1 : 0); }

struct Expected {
  std::vector<CrossingDirection> dirs;
  std::vector<mpq_class> t;  ///< exact t of each crossing
  std::size_t point_touches = 0;
  std::size_t shared = 0;  ///< contacts where two or more triangles meet the ray
  std::vector<std::vector<std::uint32_t>> tris;  ///< per crossing: the triangles crossed in its direction there
};

/// The crossings of the ray from o + (e, e^2, e^3), e = 2^-40 (far below every nonzero determinant of
/// the lattice inputs used here), grouped by the exact t of the unmoved ray's contact, t >= 0.
Expected brute(const Shape& s, const Ray<double>& r) {
  const mpq_class e = mpq_class(1, 1) / mpq_class(mpz_class(1) << 40);
  const Q3 o = q3(r.o), d = q3(r.d), op = o + Q3{e, e * e, e * e * e};
  std::map<mpq_class, int> net;  // exact t of a contact -> net crossings of the moved ray there
  std::map<mpq_class, std::vector<std::pair<int, std::uint32_t>>> who;  // direction, triangle
  std::map<mpq_class, int> met_at;
  for (std::uint32_t ti = 0; ti < s.t.size(); ++ti) {
    const Tri& tri = s.t[ti];
    const Q3 p[3] = {q3(s.v[tri[0]]), q3(s.v[tri[1]]), q3(s.v[tri[2]])};
    const Q3 n = cross(p[1] - p[0], p[2] - p[0]);
    const mpq_class den = dot(d, n);
    if (sgn(den) == 0) continue;  // parallel or coplanar: never crossed, not a point contact
    const mpq_class t = dot(p[0] - o, n) / den;
    if (sgn(t) < 0) continue;
    // The unmoved ray meets the closed triangle: barycentric volumes of the sign of den or 0.
    bool met = true, crossed = true;
    for (int i = 0; i < 3; ++i) {
      const Q3 &a = p[(i + 1) % 3], &b = p[(i + 2) % 3];
      const int u = sgn(dot(d, cross(a - o, b - o))), up = sgn(dot(d, cross(a - op, b - op)));
      met = met && u != -sgn(den);
      crossed = crossed && up == sgn(den);
    }
    if (!met) continue;
    int& k = net[t];
    ++met_at[t];
    if (crossed) k += sgn(den) < 0 ? 1 : -1, who[t].push_back({sgn(den) < 0 ? 1 : -1, ti});
  }
  Expected x;
  for (const auto& [t, k] : net) {
    if (k == 0) ++x.point_touches;
    if (met_at[t] > 1) ++x.shared;
    std::vector<std::uint32_t> tris;
    for (const auto& [dir, tri] : who[t])
      if (dir * k > 0) tris.push_back(tri);
    for (int i = 0; i < std::abs(k); ++i) x.dirs.push_back(k > 0 ? In : Out), x.t.push_back(t), x.tris.push_back(tris);
  }
  return x;
}

/// The surface of [0, n]^3 split into unit squares, each cut along a random diagonal; vertices
/// then moved along random axes by multiples of 1/4 (bumpy: still closed and oriented, maybe
/// self-intersecting).
Shape lattice_box(int n, std::mt19937& rng, bool bumpy) {
  Shape s;
  std::map<std::array<int, 3>, std::uint32_t> index;
  auto vid = [&](int x, int y, int z) {
    const auto [it, fresh] = index.try_emplace({x, y, z}, std::uint32_t(s.v.size()));
    if (fresh) s.v.push_back({double(x), double(y), double(z)});
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            std::array<int, 3> c{};
            c[axis] = side * n, c[(axis + 1) % 3] = a, c[(axis + 2) % 3] = b;
            return vid(c[0], c[1], c[2]);
          };
          std::uint32_t q[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
          // (axis+1, axis+2) counterclockwise seen from +axis: outward on side 1, flipped on side 0.
          if (side == 0) std::swap(q[1], q[3]);
          if (rng() & 1) {
            s.t.push_back({q[0], q[1], q[2]}), s.t.push_back({q[0], q[2], q[3]});
          } else {
            s.t.push_back({q[0], q[1], q[3]}), s.t.push_back({q[1], q[2], q[3]});
          }
        }
  if (bumpy) {
    for (auto& p : s.v) {
      const int k = int(rng() % 3), m = int(rng() % 3) - 1;
      (k == 0 ? p.x : (k == 1 ? p.y : p.z)) += 0.25 * m;
    }
    }
  return s;
}

/// Random rays from lattice points in multiples of 1/2 with small integer directions: many pass
/// through edges and vertices, many lie in face planes.
Ray<double> lattice_ray(std::mt19937& rng, int n) {
  auto c = [&] { return 0.5 * double(int(rng() % (4 * n + 9)) - 4); };
  auto dc = [&] { return double(int(rng() % 5) - 2); };
  Ray<double> r{{c(), c(), c()}, {dc(), dc(), dc()}};
  while (r.d.x == 0 && r.d.y == 0 && r.d.z == 0) r.d = {dc(), dc(), dc()};
  return r;
}

void check_against_brute(const Shape& s, int n, int rays, std::uint32_t seed, bool closed_oriented) {
  const ExactMesh m = make(s);
  std::mt19937 rng(seed);
  std::size_t edge_or_vertex = 0, touched = 0, coplanar = 0, checked_winding = 0;
  for (int i = 0; i < rays; ++i) {
    const Ray<double> r = lattice_ray(rng, n);
    const RayCrossings got = m.ray_crossings(r);
    const Expected want = brute(s, r);
    ASSERT_EQ(dirs(got), want.dirs) << "ray " << i << " o (" << r.o.x << ", " << r.o.y << ", " << r.o.z << ") d ("
                                    << r.d.x << ", " << r.d.y << ", " << r.d.z << ")";
    for (std::size_t k = 1; k < got.crossings.size(); ++k) EXPECT_LE(got.crossings[k - 1].t, got.crossings[k].t);
    for (std::size_t k = 0; k < want.t.size(); ++k) {
      const double t = got.crossings[k].t, exact = want.t[k].get_d();
      EXPECT_LE(std::fabs(t - exact), std::nextafter(std::fabs(exact), INFINITY) - std::fabs(exact)) << "ray " << i;
    }
    std::size_t point_touches = 0;
    for (const auto& t : got.touches) {
      point_touches += t.contact != Contact::coplanar;
      coplanar += t.contact == Contact::coplanar;
    }
    EXPECT_EQ(point_touches, want.point_touches) << "ray " << i;
    edge_or_vertex += want.shared;
    touched += point_touches;
    for (std::size_t k = 0; k < want.t.size(); ++k) {
      const auto& ok = want.tris[k];
      EXPECT_TRUE(std::find(ok.begin(), ok.end(), got.crossings[k].triangle) != ok.end()) << "ray " << i;
    }
    if (closed_oriented) {
      const std::int32_t w = m.winding(r.o);
      if (w != ExactMesh::kOnSurface) {
        EXPECT_EQ(got.net(), -w) << "ray " << i;
        ++checked_winding;
      }
    }
  }
  // The rays must have exercised the degenerate cases, not only generic crossings.
  EXPECT_GT(touched, 0u);
  EXPECT_GT(coplanar, 0u);
  EXPECT_GT(edge_or_vertex, 0u);
  if (closed_oriented) {
    EXPECT_GT(checked_winding, std::size_t(rays) / 2);
  }
}

TEST(CrossingsBrute, SmallShapes) {
  check_against_brute(cube(), 2, 3000, 11, true);
  check_against_brute(tetrahedron(), 1, 3000, 12, true);
}

TEST(CrossingsBrute, LatticeBoxes) {
  std::mt19937 rng(5);
  for (int k = 0; k < 4; ++k) check_against_brute(lattice_box(3, rng, false), 3, 1000, 100 + k, true);
}

TEST(CrossingsBrute, BumpyBoxes) {
  std::mt19937 rng(6);
  for (int k = 0; k < 4; ++k) check_against_brute(lattice_box(3, rng, true), 3, 1000, 200 + k, true);
}

TEST(CrossingsBrute, HoledBoxesAndSoups) {
  std::mt19937 rng(8);
  for (int k = 0; k < 4; ++k) {
    Shape s = lattice_box(3, rng, k % 2 == 1);
    // Cut holes: drop a random tenth of the triangles; the last one also reversed at random.
    std::vector<Tri> kept;
    for (const Tri& t : s.t)
      if (rng() % 10) kept.push_back(k == 3 && (rng() & 1) ? Tri{t[0], t[2], t[1]} : t);
    s.t = kept;
    check_against_brute(s, 3, 1000, 300 + k, false);
  }
}

TEST(Crossings, BatchMatchesSingle) {
  std::mt19937 rng(9);
  const Shape s = lattice_box(4, rng, true);
  const ExactMesh m = make(s);
  std::vector<Ray<double>> rays;
  for (int i = 0; i < 2000; ++i) rays.push_back(lattice_ray(rng, 4));
  std::vector<RayCrossings> out(rays.size());
  m.ray_crossings(rays, out, {}, 2);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const RayCrossings one = m.ray_crossings(rays[i]);
    ASSERT_EQ(dirs(out[i]), dirs(one));
    ASSERT_EQ(ts(out[i]), ts(one));
    ASSERT_EQ(out[i].touches.size(), one.touches.size());
  }
  std::vector<RayCrossings> wrong(3);
  EXPECT_THROW(m.ray_crossings(rays, wrong), rayproof::MeshInputError);
}

}  // namespace

namespace {

/// A UV sphere of n rings with radii scaled at random in [0.6, 1.4] (closed, oriented, often
/// self-intersecting), coordinates generic doubles.
Shape bumpy_sphere(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> scale(0.6, 1.4);
  Shape s;
  const double pi = std::acos(-1.0);
  s.v.push_back({0, 0, scale(rng)}), s.v.push_back({0, 0, -scale(rng)});
  for (int i = 1; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double a = pi * i / n, b = pi * j / n, r = scale(rng);
      s.v.push_back({r * std::sin(a) * std::cos(b), r * std::sin(a) * std::sin(b), r * std::cos(a)});
    }
  auto ring = [&](int i, int j) { return std::uint32_t(2 + i * 2 * n + (j % (2 * n))); };
  for (int j = 0; j < 2 * n; ++j) {
    s.t.push_back({0, ring(0, j), ring(0, j + 1)});
    s.t.push_back({1, ring(n - 2, j + 1), ring(n - 2, j)});
  }
  for (int i = 0; i + 1 < n - 1; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      s.t.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      s.t.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  return s;
}

// Many random closed meshes with generic coordinates: axis rays exactly through vertices (the
// vertex's coordinates kept, the origin moved along one axis) and random rays; the net count must
// be minus the exact winding number at the origin, and t must never decrease.
TEST(CrossingsRandomMeshes, WindingIdentityThroughVertices) {
  std::mt19937 rng(42);
  std::size_t checked = 0, vertex_contacts = 0;
  for (int mesh = 0; mesh < 40; ++mesh) {
    const Shape s = bumpy_sphere(6 + int(rng() % 6), rng);
    const ExactMesh m = make(s);
    ASSERT_TRUE(m.oriented());
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int i = 0; i < 200; ++i) {
      Ray<double> r;
      if (i % 2 == 0) {
        const Vec3<double>& v = s.v[rng() % s.v.size()];
        const int k = int(rng() % 3);
        const double shift = u(rng);
        r.o = v;
        (k == 0 ? r.o.x : (k == 1 ? r.o.y : r.o.z)) += shift;
        r.d = {0, 0, 0};
        (k == 0 ? r.d.x : (k == 1 ? r.d.y : r.d.z)) = shift > 0 ? -1 : 1;
      } else {
        r = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
      }
      const RayCrossings got = m.ray_crossings(r);
      for (std::size_t k = 1; k < got.crossings.size(); ++k) ASSERT_LE(got.crossings[k - 1].t, got.crossings[k].t);
      for (const auto& t : got.touches) vertex_contacts += t.contact == Contact::vertex;
      const std::int32_t w = m.winding(r.o);
      if (w == ExactMesh::kOnSurface) continue;
      ASSERT_EQ(got.net(), -w) << "mesh " << mesh << " ray " << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 7000u);
  EXPECT_GT(vertex_contacts, 0u);
}

}  // namespace

namespace {

// Far from 1: the cube and its rays scaled by 2^-600 and 2^600 (outside the expansions' exponent
// window: the GMP paths) give the unscaled answers, t included (t does not change when o and d scale
// together).
TEST(Crossings, ScaledFarFromOne) {
  const Ray<double> rays[] = {ray({-1, 0.5, 0.75}, {1, 0, 0}), ray({-1, -1, 0.5}, {1, 1, 0}), ray({-1, -1, -1}, {1, 1, 1}),
                              ray({-1, 1, 1}, {1, 0, 1}), ray({-1, 1, 2}, {1, 0, 0}), ray({-1, 1, 0}, {1, 0, 0})};
  const ExactMesh unit = make(cube());
  for (const double f : {0x1p-600, 0x1p600}) {
    Shape s = cube();
    for (auto& p : s.v) p = {p.x * f, p.y * f, p.z * f};
    const ExactMesh m = make(s);
    for (const auto& r : rays) {
      const RayCrossings a = unit.ray_crossings(r);
      const RayCrossings b = m.ray_crossings(ray({r.o.x * f, r.o.y * f, r.o.z * f}, {r.d.x * f, r.d.y * f, r.d.z * f}));
      EXPECT_EQ(dirs(a), dirs(b)) << f;
      EXPECT_EQ(ts(a), ts(b)) << f;
      EXPECT_EQ(a.touches.size(), b.touches.size()) << f;
    }
  }
}

}  // namespace
