// check_distance (rayproof/verify/distance_check.h): rayproof's own distances get no finding; a
// double point-triangle distance written the textbook way, a function off by a relative 1e-9, one
// with flipped signs and one answering numbers at NaN points get exactly the counts of a brute-force
// tally: the exact distance as the least correctly rounded distance to each triangle
// (exact_triangle_distance), the side from the generalized winding number over every triangle.
// Closest points and triangles: rayproof's own get no finding; hand-made wrong ones (off the mesh,
// on it but not nearest, a triangle not at the exact distance) each move their counter only, and
// every count equals the brute-force tally (the nearest triangles compared exactly, pairwise). The
// float precision: the mesh and points rounded to float, errors in float ulps.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/winding.h"
#include "rayproof/verify/distance_check.h"
#include "rayproof/verify/distance_gtest.h"

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

std::array<Vec3<double>, 3> corners(const OwnedMesh& m, std::size_t t) {
  return {m.v[m.f[t][0]], m.v[m.f[t][1]], m.v[m.f[t][2]]};
}

/// The spacing of doubles (or floats) above |v|: nextafter, not frexp as the judge.
double spacing(double v, bool float32) {
  if (float32) {
    const float f = std::fabs(static_cast<float>(v));
    return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) - f;
  }
  return std::nextafter(std::fabs(v), std::numeric_limits<double>::infinity()) - std::fabs(v);
}

/// The closest point's and triangle's counts, brute force: every triangle's exact distance.
void brute_columns(const OwnedMesh& m, bool float32, const Vec3<double>& p, const DistanceAnswer& a, DistanceCounts& c) {
  std::size_t nearest = 0;  // a nearest triangle: exact pairwise comparisons
  for (std::size_t t = 1; t < m.f.size(); ++t)
    if (compare_triangle_distances(p, corners(m, t), corners(m, nearest)) < 0) nearest = t;
  if (a.has_point) {
    ++c.closest_points;
    const Vec3<double>& x = a.point;
    if (!finite(x)) {
      ++c.closest_off_mesh;
    } else {
      const double b = 2 * std::max({spacing(x.x, float32), spacing(x.y, float32), spacing(x.z, float32)});
      double off = std::numeric_limits<double>::infinity();
      for (std::size_t t = 0; t < m.f.size(); ++t) off = std::min(off, exact_triangle_distance(x, corners(m, t)));
      if (off > b) ++c.closest_off_mesh;
      if (exact_triangle_distance(p, {x, x, x}) - exact_triangle_distance(p, corners(m, nearest)) > b)
        ++c.closest_not_nearest;
    }
  }
  if (a.has_triangle) {
    ++c.triangle_ids;
    if (a.triangle < 0 || a.triangle >= static_cast<std::int64_t>(m.f.size()) ||
        compare_triangle_distances(p, corners(m, static_cast<std::size_t>(a.triangle)), corners(m, nearest)) != 0)
      ++c.wrong_triangle;
  }
}

DistanceCounts brute_tally(const OwnedMesh& m, const verify::DistanceCheckOptions& opt,
                           const verify::ContainsPoints& pts, std::span<const DistanceAnswer> answers) {
  const bool float32 = opt.precision == verify::ContainsPrecision::float32;
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
    brute_columns(m, float32, pts.points[i], a, c);
    const double d = a.distance;
    if (std::isnan(d) || (!opt.signed_distance && d < 0)) {
      ++c.garbage;
      continue;
    }
    if (exact == 0 && d != 0) ++c.surface_nonzero;
    if (opt.signed_distance && d != 0 && exact != 0 && (d < 0) != (exact < 0)) ++c.wrong_sign;
    const std::uint64_t ulps =
        float32 ? ulp_distance(static_cast<float>(d), static_cast<float>(exact)) : ulp_distance(d, exact);
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

template <class Function>
Judged run(const OwnedMesh& m, const Function& fn, verify::DistanceCheckOptions opt = {}) {
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
    if (rel_tol > 0) {
      EXPECT_EQ(r.tally.over_tolerance, r.tally.wrong_sign) << verify::summary_text(r.tally);
    }
  }
}

TEST(DistanceCheck, SurfaceNonzeroAndGarbageWithExactReproducers) {
  const OwnedMesh m = cube();
  const std::vector<Vec3<double>> pts{{1, 0.5, 0.5}, {std::nextafter(1.0, 2.0), 0.5, 0.5}, {0.5, 0.5, 0.5}};
  const auto fn = [](std::span<const Vec3<double>>, std::span<double> out) {
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

/// rayproof's own answers with their closest points and triangles (ExactMesh::closest_point).
verify::DistanceAnswerFunction exact_answers(const ExactMesh& mesh, bool with_sign) {
  return [&mesh, with_sign](std::span<const Vec3<double>> p, std::span<DistanceAnswer> out) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const ClosestPoint c = mesh.closest_point(p[i], with_sign);
      out[i].distance = with_sign ? c.signed_distance() : c.distance;
      out[i].point = c.point, out[i].has_point = true;
      out[i].triangle = c.triangle == ClosestPoint::kNoTriangle ? -1 : c.triangle, out[i].has_triangle = true;
    }
  };
}

ExactMesh exact_mesh(const OwnedMesh& m) {
  return ExactMesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
}

// The GoogleTest helper: the exact function passes (unsigned by the macro, signed through the
// options); a function answering 0 everywhere fails with its counts and a reproducer line.
TEST(DistanceCheck, GoogleTestMacroPassesTheExactFunctionAndExplainsAWrongOne) {
  const OwnedMesh m = cube();
  const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  EXPECT_DISTANCE_MATCHES_EXACT(exact_function(mesh, false), m.view());
  verify::DistanceCheckOptions signed_opt;
  signed_opt.signed_distance = true;
  EXPECT_TRUE(gtest::distance_matches_exact(exact_function(mesh, true), m.view(), signed_opt));
  // Unsigned answers judged as signed: every inside point has the wrong sign.
  EXPECT_FALSE(gtest::distance_matches_exact(exact_function(mesh, false), m.view(), signed_opt));
  const auto zero = [](std::span<const Vec3<double>>, std::span<double> out) { std::fill(out.begin(), out.end(), 0.0); };
  const ::testing::AssertionResult wrong = gtest::distance_matches_exact(zero, m.view());
  EXPECT_FALSE(wrong);
  const std::string text = wrong.message();
  EXPECT_NE(text.find("the distance function differs from exact on "), std::string::npos) << text;
  EXPECT_NE(text.find(" mesh=" + m.name + " point "), std::string::npos) << text;
  // Closest points and triangles: rayproof's own answers pass.
  EXPECT_DISTANCE_MATCHES_EXACT(exact_answers(mesh, false), m.view());
}

TEST(DistanceCheck, ExactClosestPointsAndTrianglesHaveNoFinding) {
  for (const OwnedMesh& m : {cube(), tetrahedron()})
    for (bool with_sign : {false, true}) {
      const ExactMesh mesh = exact_mesh(m);
      verify::DistanceCheckOptions opt;
      opt.signed_distance = with_sign;
      const Judged r = run(m, exact_answers(mesh, with_sign), opt);
      EXPECT_EQ(r.tally.findings(), 0u) << m.name << "\n" << verify::summary_text(r.tally);
      EXPECT_EQ(r.tally.closest_points, r.tally.points - r.tally.invalid_points) << m.name;
      EXPECT_EQ(r.tally.triangle_ids, r.tally.closest_points) << m.name;
      expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), m.name);
    }
}

// Each wrong answer moves its counter and no other finding's: the closest point halfway to the
// point (off the mesh, nearer), the mesh's vertex farthest from the point (on the mesh, not
// nearest), the next triangle (not at the exact distance unless tied), a NaN point, no such triangle.
TEST(DistanceCheck, WrongClosestPointsAndTrianglesMoveTheirCounterOnly) {
  const OwnedMesh m = tetrahedron();
  const ExactMesh mesh = exact_mesh(m);
  struct Wrong {
    const char* name;
    std::uint64_t DistanceCounts::*counter;
    std::function<void(const Vec3<double>&, DistanceAnswer&)> change;
  };
  const std::vector<Wrong> wrongs = {
      {"halfway", &DistanceCounts::closest_off_mesh,
       [](const Vec3<double>& p, DistanceAnswer& a) { a.point = a.point + 0.5 * (p - a.point); }},
      {"far vertex", &DistanceCounts::closest_not_nearest,
       [&m](const Vec3<double>& p, DistanceAnswer& a) {
         for (const Vec3<double>& v : m.v)
           if (length(v - p) > length(a.point - p)) a.point = v;
       }},
      {"next triangle", &DistanceCounts::wrong_triangle,
       [&m](const Vec3<double>&, DistanceAnswer& a) {
         a.triangle = (a.triangle + 1) % static_cast<std::int64_t>(m.f.size());
       }},
      {"nan point", &DistanceCounts::closest_off_mesh,
       [](const Vec3<double>&, DistanceAnswer& a) { a.point.y = kNaN<double>; }},
      {"no such triangle", &DistanceCounts::wrong_triangle, [](const Vec3<double>&, DistanceAnswer& a) { a.triangle = 4; }},
  };
  const verify::DistanceCheckOptions opt;
  const Judged right = run(m, exact_answers(mesh, false), opt);
  for (const Wrong& w : wrongs) {
    const auto exact = exact_answers(mesh, false);
    std::size_t seen = 0;
    const verify::DistanceAnswerFunction fn = [&](std::span<const Vec3<double>> p, std::span<DistanceAnswer> out) {
      exact(p, out);
      for (std::size_t i = 0; i < p.size(); ++i)
        if (seen++ % 3 == 0 && finite(p[i])) w.change(p[i], out[i]);
    };
    const Judged r = run(m, fn, opt);
    expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), w.name);
    EXPECT_GT(r.tally.*w.counter, 0u) << w.name << "\n" << verify::summary_text(r.tally);
    EXPECT_EQ(r.tally.findings(), r.tally.*w.counter) << w.name << "\n" << verify::summary_text(r.tally);
    EXPECT_EQ(r.tally.closest_points, right.tally.closest_points) << w.name;
  }
}

/// The triangles at exactly the least distance from p (exact pairwise comparisons).
std::vector<std::size_t> exact_ties(const OwnedMesh& m, const Vec3<double>& p) {
  std::size_t nearest = 0;
  for (std::size_t t = 1; t < m.f.size(); ++t)
    if (compare_triangle_distances(p, corners(m, t), corners(m, nearest)) < 0) nearest = t;
  std::vector<std::size_t> ties;
  for (std::size_t t = 0; t < m.f.size(); ++t)
    if (compare_triangle_distances(p, corners(m, t), corners(m, nearest)) == 0) ties.push_back(t);
  return ties;
}

// The medial set on the cube: every point is an exact tie of two triangles or more (bisectors of
// mirrored faces). rayproof's own answers get no finding; answering another tied triangle is not
// wrong; answering a triangle that is not tied is, and every count equals the brute-force tally.
TEST(DistanceCheck, MedialPointsAreTiesAndAnyTiedTriangleIsRight) {
  const OwnedMesh m = cube();
  const ExactMesh mesh = exact_mesh(m);
  verify::DistanceCheckOptions opt;
  opt.sets = {"medial"};
  opt.max_points_per_set = 100000;
  const verify::ContainsPoints pts = verify::distance_points(m.view(), opt);
  ASSERT_EQ(pts.names, std::vector<std::string>{"medial"});
  // 18 edges (12 of the cube, 6 diagonals), 3 distances both ways.
  EXPECT_EQ(pts.points.size(), 18u * 6u);
  for (const Vec3<double>& p : pts.points) EXPECT_GE(exact_ties(m, p).size(), 2u) << p.x << " " << p.y << " " << p.z;
  const auto exact = exact_answers(mesh, false);
  for (const char* how : {"exact", "other tie", "not tied"}) {
    std::size_t not_tied = 0;
    const verify::DistanceAnswerFunction fn = [&](std::span<const Vec3<double>> p, std::span<DistanceAnswer> out) {
      exact(p, out);
      for (std::size_t i = 0; i < p.size(); ++i) {
        const std::vector<std::size_t> ties = exact_ties(m, p[i]);
        if (std::string(how) == "other tie") {
          for (std::size_t t : ties)
            if (static_cast<std::int64_t>(t) != out[i].triangle) out[i].triangle = static_cast<std::int64_t>(t);
        } else if (std::string(how) == "not tied") {
          for (std::size_t t = 0; t < m.f.size(); ++t)
            if (std::find(ties.begin(), ties.end(), t) == ties.end()) {
              out[i].triangle = static_cast<std::int64_t>(t), ++not_tied;
              break;
            }
        }
      }
    };
    const Judged r = run(m, fn, opt);
    expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), how);
    EXPECT_EQ(r.tally.points, pts.points.size()) << how;
    EXPECT_EQ(r.tally.findings(), r.tally.wrong_triangle) << how << "\n" << verify::summary_text(r.tally);
    EXPECT_EQ(r.tally.wrong_triangle, not_tied) << how;
    if (std::string(how) == "not tied") {
      EXPECT_EQ(not_tied, pts.points.size());
    }
  }
}

TEST(DistanceCheck, ClosestPointReproducersAreExact) {
  const OwnedMesh m = cube();
  const std::vector<Vec3<double>> pts{{0.5, 0.5, 2}, {0.5, 0.5, 3}};
  const verify::DistanceAnswerFunction fn = [](std::span<const Vec3<double>>, std::span<DistanceAnswer> out) {
    out[0] = {.distance = 1, .point = {0.5, 0.5, 1.25}, .triangle = 0, .has_point = true, .has_triangle = true};
    out[1] = {.distance = 2, .point = {0, 0, 1}, .triangle = 2, .has_point = true, .has_triangle = true};
  };
  const verify::DistanceTally t = verify::check_distance(fn, m.view(), pts);
  EXPECT_EQ(t.closest_off_mesh, 1u);
  EXPECT_EQ(t.closest_not_nearest, 1u);
  EXPECT_EQ(t.wrong_triangle, 1u);
  EXPECT_EQ(t.findings(), 3u) << verify::summary_text(t);
  const std::string text = verify::summary_text(t);
  for (const char* line :
       {"closest-off-mesh set=user mesh=cube point 0.5 0.5 2 exact: 1 (triangle 2) answer: 1 closest 0.5 0.5 1.25 "
        "(0.25 from the mesh, bound 4.440892098500626e-16)",
        "closest-not-nearest set=user mesh=cube point 0.5 0.5 3 exact: 2 (triangle 2) answer: 2 closest 0 0 1 "
        "(2.1213203435596424 from the point, bound 4.440892098500626e-16)",
        "wrong-triangle set=user mesh=cube point 0.5 0.5 2 exact: 1 (triangle 2) answer: 1 triangle 0 (exact distance 2)"})
    EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
}

// The bound's edge: b(x) = 2 ulps of 1 = 2^-51 at the cube's top face (point 0.5 0.5 2, exact
// nearest triangle 2): a closest point 2 ulps above the face is on the mesh, 3 ulps above is off it
// (and nearer the point); one on the side face x = 1, 2.5 ulps below the top edge, is on the mesh
// (though farther than b(x) from triangle 2) and not nearest; 3 and 1.5 ulps of 1 below the top
// face (b(x) = 2^-52 there) are off the mesh and not nearest (that much farther than 1 from the point).
TEST(DistanceCheck, ClosestPointsAtTheBoundsEdge) {
  const OwnedMesh m = cube();
  const double u = std::ldexp(1.0, -52);
  const std::vector<Vec3<double>> xs{{0.5, 0.5, 1 + 2 * u}, {0.5, 0.5, 1 + 3 * u}, {1, 0.5, 1 - 2.5 * u}, {0.5, 0.5, 1 - 3 * u},
                                     {0.5, 0.5, 1 - 1.5 * u}};
  const std::uint64_t off[] = {0, 1, 0, 1, 1}, not_nearest[] = {0, 0, 1, 1, 1};
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const std::vector<Vec3<double>> pts(1, Vec3<double>{0.5, 0.5, 2});
    const verify::DistanceAnswerFunction fn = [&](std::span<const Vec3<double>>, std::span<DistanceAnswer> out) {
      out[0] = {.distance = 1, .point = xs[k], .has_point = true};
    };
    const verify::DistanceTally t = verify::check_distance(fn, m.view(), pts);
    EXPECT_EQ(t.closest_points, 1u) << k;
    EXPECT_EQ(t.closest_off_mesh, off[k]) << k << "\n" << verify::summary_text(t);
    EXPECT_EQ(t.closest_not_nearest, not_nearest[k]) << k << "\n" << verify::summary_text(t);
  }
}

// The judge decides the closest points' tests in long double where its error bound can tell
// (verify/distance_filter.h), in rationals where not: answered points placed exactly on the
// nearest triangle (a corner), rounded onto its edges and face, the exact closest point, and those
// moved 1 to 4 ulps per coordinate, beside exact and neighbouring triangles, get every count of
// the brute-force tally, on a mesh of generic coordinates and on the thin tetrahedron, in double
// and in float.
TEST(DistanceCheck, ClosestPointsOnOneUlpOffEdgesAndCornersCountAsTheBruteForceTally) {
  OwnedMesh octahedron{{}, {}, "perturbed-octahedron"};
  for (int k = 0; k < 6; ++k) {
    Vec3<double> v{0.0007 * k, -0.0003 * k, 0.0011 / (k + 1)};
    const double r = (k % 2 == 0 ? 1 : -1) * (0.9 + k / 7.0);
    (k / 2 == 0 ? v.x : (k / 2 == 1 ? v.y : v.z)) += r;
    octahedron.v.push_back(v);
  }
  octahedron.f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const auto step = [](const Vec3<double>& x, int kx, int ky, int kz) {
    auto one = [](double v, int k) {
      for (; k > 0; --k) v = std::nextafter(v, std::numeric_limits<double>::infinity());
      for (; k < 0; ++k) v = std::nextafter(v, -std::numeric_limits<double>::infinity());
      return v;
    };
    return Vec3<double>{one(x.x, kx), one(x.y, ky), one(x.z, kz)};
  };
  for (const bool float32 : {false, true})
    for (const OwnedMesh& given : {octahedron, tetrahedron()}) {
      OwnedMesh m = given;
      if (float32) m.v = verify::float_vertices(m.v);
      const ExactMesh mesh = exact_mesh(m);
      std::size_t seen = 0;
      const verify::DistanceAnswerFunction fn = [&](std::span<const Vec3<double>> p, std::span<DistanceAnswer> out) {
        exact_answers(mesh, false)(p, out);
        for (std::size_t i = 0; i < p.size(); ++i, ++seen) {
          DistanceAnswer& a = out[i];
          if (!finite(p[i]) || a.triangle < 0) continue;
          const std::array<Vec3<double>, 3> t = corners(m, static_cast<std::size_t>(a.triangle));
          const Vec3<double> centroid = (t[0] + t[1] + t[2]) / 3.0, mid = 0.5 * (t[1] + t[2]);
          switch (seen % 8) {
            case 1: a.point = step(a.point, 1, 0, 0); break;
            case 2: a.point = step(a.point, -1, 1, -1); break;
            case 3: a.point = t[0]; break;
            case 4: a.point = mid; break;
            case 5: a.point = centroid; break;
            case 6: a.point = step(centroid, 3, -3, 3); break;
            case 7: a.point = step(a.point, 4, -4, 4); break;
            default: break;
          }
          if (seen % 3 == 1) a.triangle = (a.triangle + 1) % static_cast<std::int64_t>(m.f.size());
        }
      };
      verify::DistanceCheckOptions opt;
      if (float32) opt.precision = verify::ContainsPrecision::float32;
      const Judged r = run(m, fn, opt);
      const std::string what = m.name + (float32 ? ", float" : ", double");
      expect_counts_equal(r.tally, brute_tally(m, opt, r.points, r.answers), what);
      if (!float32) {  // 4 ulps of double are within b(x) in float ulps
        EXPECT_GT(r.tally.closest_off_mesh, 0u) << what << "\n" << verify::summary_text(r.tally);
      }
      EXPECT_GT(r.tally.closest_not_nearest, 0u) << what << "\n" << verify::summary_text(r.tally);
      EXPECT_LT(r.tally.closest_off_mesh, r.tally.closest_points / 4) << what << "\n" << verify::summary_text(r.tally);
    }
}

// Float precision: the cube scaled by 0.1 (not floats) is judged rounded to float; rayproof's exact
// answers on that rounded mesh have no finding, a double answer 1e-12 off is within 1 ulp of float
// (and not of double), one 3 float ulps off is counted; each as the brute-force tally in float ulps.
TEST(DistanceCheck, FloatPrecisionJudgesTheRoundedInputInFloatUlps) {
  OwnedMesh m = cube();
  for (Vec3<double>& v : m.v) v = 0.1 * v;
  OwnedMesh rounded = m;
  rounded.v = verify::float_vertices(m.v);
  EXPECT_NE(rounded.v[7].x, m.v[7].x);
  const ExactMesh mesh = exact_mesh(rounded);
  verify::DistanceCheckOptions opt;
  opt.precision = verify::ContainsPrecision::float32;
  for (const double off : {0.0, 1e-12, -1.0}) {
    const auto exact = exact_answers(mesh, false);
    const verify::DistanceAnswerFunction fn = [&](std::span<const Vec3<double>> p, std::span<DistanceAnswer> out) {
      exact(p, out);
      for (DistanceAnswer& a : out) {
        if (off >= 0) a.distance *= 1 + off;
        else if (a.distance > 0) a.distance = std::nextafter(std::nextafter(std::nextafter(float(a.distance), 1.f), 1.f), 1.f);
      }
    };
    const Judged r = run(rounded, fn, opt);
    for (const Vec3<double>& p : r.points.points) {
      if (finite(p)) {
        ASSERT_EQ(p.x, static_cast<float>(p.x));
      }
    }
    expect_counts_equal(r.tally, brute_tally(rounded, opt, r.points, r.answers), "float, off " + std::to_string(off));
    if (off >= 0) {
      EXPECT_EQ(r.tally.findings(), 0u) << verify::summary_text(r.tally);
    } else {
      EXPECT_GT(r.tally.over_tolerance, 0u) << verify::summary_text(r.tally);
    }
    verify::DistanceCheckOptions in_double = opt;
    in_double.precision = verify::ContainsPrecision::float64;
    const verify::DistanceTally d = verify::DistanceJudge(rounded.view()).judge(r.points, r.answers, in_double);
    if (off > 0) {
      EXPECT_GT(d.over_tolerance, 0u) << verify::summary_text(d);
    }
  }
  // check_distance rounds the mesh itself; a mesh beyond float's range is refused.
  const verify::DistanceTally t = verify::check_distance(exact_answers(mesh, false), m.view(), opt);
  EXPECT_EQ(t.findings(), 0u) << verify::summary_text(t);
  OwnedMesh huge = m;
  huge.v[7].x = 1e300;
  EXPECT_THROW((void)verify::check_distance(exact_answers(mesh, false), huge.view(), opt), std::invalid_argument);
}

}  // namespace
}  // namespace rayproof
