// check_distance (rayproof/verify/distance_check.h): rayproof's own distances get no finding; a
// double point-triangle distance written the textbook way, a function off by a relative 1e-9, one
// with flipped signs and one answering numbers at NaN points get exactly the counts of a brute-force
// tally: the exact distance as the least correctly rounded distance to each triangle
// (exact_triangle_distance), the side from the generalized winding number over every triangle.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/winding.h"
#include "rayproof/verify/distance_check.h"

namespace rayproof {
namespace {

using verify::DistanceAnswer;
using verify::DistanceCounts;
using Tri = std::array<std::uint32_t, 3>;

struct OwnedMesh {
  std::vector<Vec3<double>> v;
  std::vector<Tri> f;
  std::string name;
  [[nodiscard]] verify::ContainsMesh view() const { return {v, f, name}; }
};

OwnedMesh cube() {
  OwnedMesh m{{}, {}, "cube"};
  for (int i = 0; i < 8; ++i) m.v.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) m.f.push_back({f[0], f[1], f[2]}), m.f.push_back({f[0], f[2], f[3]});
  return m;
}
OwnedMesh tetrahedron() {
  return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 1e-3}}, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}},
          "thin-tetrahedron"};
}

bool finite(const Vec3<double>& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// The brute-force exact (signed) distance: NaN for an invalid point.
double brute(const OwnedMesh& m, const Vec3<double>& p, bool with_sign) {
  if (!finite(p)) return kNaN<double>;
  double d = std::numeric_limits<double>::infinity();
  for (const Tri& t : m.f) d = std::min(d, exact_triangle_distance(p, {m.v[t[0]], m.v[t[1]], m.v[t[2]]}));
  if (!with_sign || d == 0) return d;
  const WindingValue w = winding_brute_force(m.v, m.f, p);
  return std::lround(w.w) != 0 ? -d : d;  // closed oriented meshes: the integer winding number
}

DistanceCounts brute_tally(const OwnedMesh& m, const verify::DistanceCheckOptions& opt,
                           const verify::ContainsPoints& pts, std::span<const DistanceAnswer> answers) {
  DistanceCounts c;
  for (std::size_t i = 0; i < pts.points.size(); ++i) {
    const DistanceAnswer& a = answers[i];
    ++c.points;
    if (!finite(pts.points[i])) {
      ++c.invalid_points;
      if (a.failed) ++c.invalid_failures;
      else if (!std::isnan(a.distance)) ++c.invalid_number;
      continue;
    }
    const double exact = brute(m, pts.points[i], opt.signed_distance);
    if (exact == 0) ++c.surface;
    if (a.failed) {
      ++c.failures;
      continue;
    }
    const double d = a.distance;
    if (std::isnan(d) || (!opt.signed_distance && d < 0)) {
      ++c.garbage;
      continue;
    }
    if (exact == 0 && d != 0) ++c.surface_nonzero;
    if (opt.signed_distance && d != 0 && exact != 0 && (d < 0) != (exact < 0)) ++c.wrong_sign;
    const std::uint64_t ulps = ulp_distance(d, exact);
    c.max_ulps = std::max(c.max_ulps, ulps);
    if (ulps <= 1) continue;
    ++c.over_1ulp;
    if (!(std::fabs(d - exact) <= opt.rel_tol * std::fabs(exact))) ++c.over_tolerance;
  }
  return c;
}

void expect_counts_equal(const DistanceCounts& got, const DistanceCounts& want, const std::string& what) {
  for (const verify::DistanceCounter& counter : verify::kDistanceCounters)
    EXPECT_EQ(verify::count_of(got, counter), verify::count_of(want, counter)) << what << ": " << counter.key;
}

/// The textbook closest point on a triangle (Ericson, Real-Time Collision Detection 5.1.5) in double.
double naive_distance(const OwnedMesh& m, const Vec3<double>& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Tri& t : m.f) {
    const Vec3<double> a = m.v[t[0]], b = m.v[t[1]], c = m.v[t[2]];
    const Vec3<double> ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    Vec3<double> q;
    if (d1 <= 0 && d2 <= 0) q = a;
    else {
      const Vec3<double> bp = p - b;
      const double d3 = dot(ab, bp), d4 = dot(ac, bp);
      const Vec3<double> cp = p - c;
      const double d5 = dot(ab, cp), d6 = dot(ac, cp);
      const double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
      if (d3 >= 0 && d4 <= d3) q = b;
      else if (vc <= 0 && d1 >= 0 && d3 <= 0) q = a + (d1 / (d1 - d3)) * ab;
      else if (d6 >= 0 && d5 <= d6) q = c;
      else if (vb <= 0 && d2 >= 0 && d6 <= 0) q = a + (d2 / (d2 - d6)) * ac;
      else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) q = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
      else {
        const double den = 1 / (va + vb + vc);
        q = a + (vb * den) * ab + (vc * den) * ac;
      }
    }
    best = std::min(best, length(p - q));
  }
  return best;
}

struct Judged {
  verify::ContainsPoints points;
  std::vector<DistanceAnswer> answers;
  verify::DistanceTally tally;
};

Judged run(const OwnedMesh& m, const verify::DistanceFunction& fn, verify::DistanceCheckOptions opt = {}) {
  opt.random_points = 200;
  opt.max_points_per_set = 200;
  Judged r;
  r.points = verify::distance_points(m.view(), opt);
  r.answers.resize(r.points.points.size());
  std::string error;
  verify::run_distance(fn, r.points.points, opt.batch, r.answers, error);
  r.tally = verify::DistanceJudge(m.view()).judge(r.points, r.answers, opt);
  return r;
}

verify::DistanceFunction exact_function(const ExactMesh& mesh, bool with_sign) {
  return [&mesh, with_sign](std::span<const Vec3<double>> p, std::span<double> out) {
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = with_sign ? mesh.signed_distance(p[i]) : mesh.distance(p[i]);
  };
}

TEST(DistanceCheck, ExactFunctionHasNoFinding) {
  for (const OwnedMesh& m : {cube(), tetrahedron()})
    for (bool with_sign : {false, true}) {
      const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
      verify::DistanceCheckOptions opt;
      opt.signed_distance = with_sign;
      const Judged r = run(m, exact_function(mesh, with_sign), opt);
      EXPECT_EQ(r.tally.findings(), 0u) << m.name << "\n" << verify::summary_text(r.tally);
      EXPECT_EQ(r.tally.max_ulps, 0u) << m.name;
      EXPECT_GT(r.tally.surface, 0u) << m.name;
      EXPECT_EQ(r.tally.invalid_points, 10u) << m.name;
      expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), m.name);
    }
}

TEST(DistanceCheck, TextbookDoubleDistanceCountsEqualTheBruteForceTally) {
  for (const OwnedMesh& m : {cube(), tetrahedron()}) {
    const auto naive = [&m](std::span<const Vec3<double>> p, std::span<double> out) {
      for (std::size_t i = 0; i < p.size(); ++i) out[i] = naive_distance(m, p[i]);
    };
    verify::DistanceCheckOptions opt;
    const Judged r = run(m, naive, opt);
    expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), m.name);
    // NaN in, inf out: std::min(inf, NaN) keeps inf, so every invalid point gets a number.
    EXPECT_EQ(r.tally.invalid_number, 10u) << verify::summary_text(r.tally);
    EXPECT_EQ(r.tally.garbage, 0u) << verify::summary_text(r.tally);
  }
}

// Off by a relative 1e-9 everywhere, signs flipped on every 5th point, a number at every invalid
// point, throwing on the second batch: exactly the tallied counts; rel_tol 1e-8 forgives the 1e-9.
TEST(DistanceCheck, WrongOnAKnownSubsetGetsExactlyTheExpectedCounts) {
  const OwnedMesh m = cube();
  const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  for (double rel_tol : {0.0, 1e-8}) {
    std::size_t offset = 0, batches = 0;
    const verify::DistanceFunction wrong = [&](std::span<const Vec3<double>> p, std::span<double> out) {
      if (batches++ == 1) {
        offset += p.size();
        throw std::runtime_error("second batch");
      }
      for (std::size_t k = 0; k < p.size(); ++k) {
        const double s = mesh.signed_distance(p[k]);
        out[k] = std::isnan(s) ? 7.0 : s * (1 + 1e-9) * ((offset + k) % 5 == 0 ? -1 : 1);
      }
      offset += p.size();
    };
    verify::DistanceCheckOptions opt;
    opt.signed_distance = true;
    opt.rel_tol = rel_tol;
    opt.batch = 101;
    const Judged r = run(m, wrong, opt);
    expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), "rel_tol " + std::to_string(rel_tol));
    EXPECT_EQ(r.tally.failures + r.tally.invalid_failures, 101u);
    EXPECT_GT(r.tally.wrong_sign, 0u);
    EXPECT_GT(r.tally.over_1ulp, r.tally.wrong_sign);
    EXPECT_EQ(r.tally.invalid_number, 10u);
    if (rel_tol > 0) EXPECT_EQ(r.tally.over_tolerance, r.tally.wrong_sign) << verify::summary_text(r.tally);
  }
}

TEST(DistanceCheck, SurfaceNonzeroAndGarbageWithExactReproducers) {
  const OwnedMesh m = cube();
  const std::vector<Vec3<double>> pts{{1, 0.5, 0.5}, {std::nextafter(1.0, 2.0), 0.5, 0.5}, {0.5, 0.5, 0.5}};
  const auto fn = [](std::span<const Vec3<double>> p, std::span<double> out) {
    out[0] = 1e-17;  // on the surface: exactly 0
    out[1] = 0;      // 2^-52 away
    out[2] = -1;     // unsigned: no distance
  };
  const verify::DistanceTally t = verify::check_distance(fn, m.view(), pts);
  EXPECT_EQ(t.surface, 1u);
  EXPECT_EQ(t.surface_nonzero, 1u);
  EXPECT_EQ(t.over_tolerance, 2u);  // 1e-17 is not 0, and 0 is not 2^-52
  EXPECT_EQ(t.garbage, 1u);
  EXPECT_EQ(t.findings(), 4u);
  bool seen = false;
  for (const auto& r : t.reproducers)
    seen = seen || r.line == "over-tolerance set=user mesh=cube point 1.0000000000000002 0.5 0.5 exact: "
                             "2.220446049250313e-16 (triangle 10) answer: 0 (4372995238176751616 ulps)";
  EXPECT_TRUE(seen) << verify::summary_text(t);
}

}  // namespace
}  // namespace rayproof
