// The distance judge's floating-point filters (verify/distance_filter.h) against the exact tests
// they stand in front of: certainly_within(x, t, b) only where exact_triangle_distance(x, t) <= b,
// and rounded_point_distance(p, x) only as exact_triangle_distance(p, {x, x, x}). The points are
// the judge's kind, within rounding of a triangle: its vertices, points of its edges and face
// rounded to double, and those moved 1 to 8 ulps per coordinate (in and off the bound b, 2 ulps of
// the largest coordinate); triangles of several scales, one spanning exponents, zero-area ones. The
// filters must also decide most of them (else the judge pays rationals as before).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "rayproof/scene/distance.h"
#include "verify/distance_filter.h"

namespace rayproof {
namespace {

using Tri = std::array<Vec3<double>, 3>;
using verify::detail::certainly_within;
using verify::detail::rounded_point_distance;

/// b(x) as the judge's: 2 ulps of the largest coordinate (a power of two).
double bound(const Vec3<double>& x) {
  const double m = std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)});
  if (m == 0) return 2 * std::numeric_limits<double>::denorm_min();
  int e = 0;
  (void)std::frexp(m, &e);
  return 2 * std::ldexp(1.0, std::max(e - 53, -1074));
}

Vec3<double> ulps(const Vec3<double>& x, int kx, int ky, int kz) {
  auto step = [](double v, int k) {
    for (; k > 0; --k) v = std::nextafter(v, std::numeric_limits<double>::infinity());
    for (; k < 0; ++k) v = std::nextafter(v, -std::numeric_limits<double>::infinity());
    return v;
  };
  return {step(x.x, kx), step(x.y, ky), step(x.z, kz)};
}

Vec3<double> combination(const Tri& t, double u, double v, double w) {
  return {u * t[0].x + v * t[1].x + w * t[2].x, u * t[0].y + v * t[1].y + w * t[2].y,
          u * t[0].z + v * t[1].z + w * t[2].z};
}

std::vector<Tri> triangles() {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Tri> out;
  for (double scale : {1e-3, 0.37, 1.0, 3e5}) {
    for (int k = 0; k < 12; ++k) {
      Tri t;
      for (Vec3<double>& v : t) v = {scale * unit(rng), scale * unit(rng), scale * unit(rng)};
      out.push_back(t);
    }
  }
  out.push_back({Vec3<double>{1e-9, 2e-9, 0}, Vec3<double>{5e3, -1e-7, 3}, Vec3<double>{0.1, 7e2, -1e-5}});  // exponents apart
  out.push_back({Vec3<double>{0.1, 0.2, 0.3}, Vec3<double>{0.1, 0.2, 0.3}, Vec3<double>{0.1, 0.2, 0.3}});  // a point
  out.push_back({Vec3<double>{0, 0, 0}, Vec3<double>{1, 2, 3}, Vec3<double>{0.5, 1, 1.5}});                 // a segment
  out.push_back({Vec3<double>{0.3, 0.1, 0.7}, Vec3<double>{0.9, -0.2, 0.1}, Vec3<double>{0.3, 0.1, 0.7}});  // two corners equal
  out.push_back({Vec3<double>{0, 0, 1}, Vec3<double>{1, 0, 1}, Vec3<double>{0, 1, 1}});                     // axis-aligned, exact
  return out;
}

/// Points within rounding of t: vertices, rounded edge and face points.
std::vector<Vec3<double>> near_points(const Tri& t, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3<double>> out(t.begin(), t.end());
  for (double s : {0.5, 1.0 / 3, 0.25, unit(rng)}) {
    out.push_back(combination(t, 1 - s, s, 0));
    out.push_back(combination(t, 0, 1 - s, s));
    out.push_back(combination(t, s, 0, 1 - s));
  }
  out.push_back(combination(t, 1.0 / 3, 1.0 / 3, 1.0 / 3));
  for (int k = 0; k < 6; ++k) {
    const double u = unit(rng), v = unit(rng) * (1 - u);
    out.push_back(combination(t, 1 - u - v, u, v));
  }
  return out;
}

TEST(DistanceFilter, AvailableOnX87LongDouble) {
  if (std::numeric_limits<long double>::digits == 64) {
    EXPECT_TRUE(verify::detail::distance_filter_available());
  }
}

TEST(DistanceFilter, WithinTheBoundOnlyWhereTheExactDistanceIs) {
  std::mt19937_64 rng(11);
  std::size_t exact_within = 0, decided = 0, on_vertices = 0, vertices_decided = 0;
  const int moves[][3] = {{0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {1, 1, 1}, {-1, -1, -1}, {2, -2, 2},
                          {3, 0, 0},  {0, 3, -3}, {4, 4, 4}, {-8, 8, -8}, {16, 0, 0}};
  for (const Tri& t : triangles()) {
    const std::vector<Vec3<double>> xs = near_points(t, rng);
    for (std::size_t j = 0; j < xs.size(); ++j)
      for (const auto& m : moves) {
        const Vec3<double> x = ulps(xs[j], m[0], m[1], m[2]);
        for (double scale : {1.0, 0.5, 0.25}) {
          const double b = scale * bound(x);
          if (b == 0) continue;  // b(x) itself is never 0
          const bool fast = certainly_within(x, t, b);
          const bool exact = exact_triangle_distance(x, t) <= b;
          ASSERT_TRUE(!fast || exact) << "x " << x.x << " " << x.y << " " << x.z << " b " << b;
          exact_within += exact, decided += fast;
          if (j < 3 && m[0] == 0 && m[1] == 0 && m[2] == 0) on_vertices += exact, vertices_decided += fast;
        }
      }
  }
  EXPECT_EQ(vertices_decided, on_vertices);
  // Most points within the bound are told so without rationals.
  EXPECT_GT(decided, exact_within * 3 / 4) << decided << " of " << exact_within;
}

TEST(DistanceFilter, CertainlyWithinRefusesWhatItCannotTell) {
  const Tri t{Vec3<double>{0, 0, 0}, Vec3<double>{1, 0, 0}, Vec3<double>{0, 1, 0}};
  EXPECT_FALSE(certainly_within({0.25, 0.25, 0}, t, 0));
  EXPECT_FALSE(certainly_within({0.25, 0.25, 0}, t, std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(certainly_within({0.25, 0.25, 1e-3}, t, 1e-4));
  EXPECT_TRUE(certainly_within({0.25, 0.25, 1e-5}, t, 1e-4));
}

TEST(DistanceFilter, RoundedPointDistanceIsTheCorrectRounding) {
  std::mt19937_64 rng(13);
  std::size_t tried = 0, decided = 0;
  auto check = [&](const Vec3<double>& p, const Vec3<double>& x) {
    const double fast = rounded_point_distance(p, x);
    ++tried;
    if (std::isnan(fast)) return;
    ++decided;
    ASSERT_EQ(fast, exact_triangle_distance(p, {x, x, x}))
        << "p " << p.x << " " << p.y << " " << p.z << " x " << x.x << " " << x.y << " " << x.z;
  };
  for (const Tri& t : triangles()) {
    const std::vector<Vec3<double>> xs = near_points(t, rng);
    std::uniform_real_distribution<double> unit(-1, 1);
    for (const Vec3<double>& x : xs)
      for (double away : {0.0, 1e-300, 1e-17, 1e-9, 0.3, 7.0, 1e30, 1e300}) {
        const Vec3<double> p{x.x + away * unit(rng), x.y + away * unit(rng), x.z + away * unit(rng)};
        check(p, x);
        check(ulps(x, 1, 0, -1), x);
      }
  }
  check({0.1, 0.2, 0.3}, {0.1, 0.2, 0.3});
  EXPECT_EQ(rounded_point_distance({0.1, 0.2, 0.3}, {0.1, 0.2, 0.3}), 0.0);
  // Beyond double's range and in the subnormals the filter leaves it to the exact path.
  EXPECT_TRUE(std::isnan(rounded_point_distance({1.5e308, 1.5e308, 0}, {-1.5e308, -1.5e308, 0})));
  EXPECT_TRUE(std::isnan(rounded_point_distance({1e-310, 0, 0}, {0, 0, 0})));
  // The distance of 3-4-5 and of a midpoint tie: exact or refused, never otherwise.
  check({3, 4, 0}, {0, 0, 0});
  check({1 + std::ldexp(1.0, -53), 0, 0}, {0, 0, 0});
  EXPECT_GT(decided, tried * 9 / 10) << decided << " of " << tried;
}

// Fans of triangles around a corner (generic coordinates, one triangle of zero area) and the
// points around it: the corner itself, rounded points of the shared edges, those 1 ulp off, and
// points at 1e-12 to 10 in random directions, whose nearest points are often the corner or an edge.
TEST(DistanceFilter, TiedOnlyWhereTheExactDistancesAre) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::size_t ties = 0, decided = 0, corner_ties = 0, corner_decided = 0;
  for (int fan = 0; fan < 12; ++fan) {
    const double scale = fan % 3 == 0 ? 1e-3 : (fan % 3 == 1 ? 0.7 : 2e4);
    const Vec3<double> c{scale * unit(rng), scale * unit(rng), scale * unit(rng)};
    std::vector<Vec3<double>> ring;
    for (int k = 0; k < 6; ++k) {
      const double angle = k * 1.0471975511965976 + 0.1 * unit(rng);
      ring.push_back({c.x + scale * std::cos(angle), c.y + scale * std::sin(angle), c.z + 0.4 * scale * unit(rng)});
    }
    std::vector<Tri> tris;
    for (int k = 0; k < 6; ++k) tris.push_back({c, ring[k], ring[(k + 1) % 6]});
    tris.push_back({c, ring[0], Vec3<double>{c.x + 2 * (ring[0].x - c.x), c.y + 2 * (ring[0].y - c.y),
                                             c.z + 2 * (ring[0].z - c.z)}});  // zero area (up to rounding)
    std::vector<Vec3<double>> ps{c};
    for (const Vec3<double>& r : ring)
      for (double s : {0.5, 0.3}) {
        const Vec3<double> e{c.x + s * (r.x - c.x), c.y + s * (r.y - c.y), c.z + s * (r.z - c.z)};
        ps.push_back(e), ps.push_back(ulps(e, 1, -1, 1)), ps.push_back(ulps(c, 1, 0, -1));
      }
    for (double away : {1e-12, 1e-6, 1e-2, 1.0, 10.0})
      for (int k = 0; k < 20; ++k)
        ps.push_back({c.x + away * scale * unit(rng), c.y + away * scale * unit(rng), c.z + away * scale * unit(rng)});
    for (const Vec3<double>& p : ps)
      for (std::size_t i = 0; i < tris.size(); ++i)
        for (std::size_t j = 0; j < tris.size(); ++j) {
          const bool fast = verify::detail::certainly_tied(p, tris[i], tris[j]);
          const bool tie = compare_triangle_distances(p, tris[i], tris[j]) == 0;
          ASSERT_TRUE(!fast || tie) << "p " << p.x << " " << p.y << " " << p.z << " triangles " << i << " " << j;
          if (i == j) continue;
          ties += tie, decided += fast;
          if (p.x == c.x && p.y == c.y && p.z == c.z) corner_ties += tie, corner_decided += fast;
        }
  }
  EXPECT_EQ(corner_decided, corner_ties);
  EXPECT_GT(decided, ties * 3 / 4) << decided << " of " << ties;
}

}  // namespace
}  // namespace rayproof
