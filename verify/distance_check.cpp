// The judgement of someone else's distance function on a mesh (rayproof/verify/distance_check.h):
// ExactMesh::closest_points gives each point's correctly rounded exact distance (and its exact side
// for signed distances); the answers are counted against it in ulps and relatively. The exact tests
// of answered closest points and triangles go through the floating-point filters of
// verify/distance_filter.h first, rationals only where they cannot tell.
#include "rayproof/verify/distance_check.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <type_traits>

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/mesh_caster.h"
#include "verify/distance_filter.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

namespace {

std::string num(double x) { return exact_number(x); }

/// The spacing of the precision's numbers at |v| (double: 53 bits, float: 24), a power of two.
double ulp_at(double v, bool float32) {
  const int bits = float32 ? 24 : 53, least = float32 ? -149 : -1074;
  if (v == 0) return std::ldexp(1.0, least);
  int e = 0;
  (void)std::frexp(v, &e);
  return std::ldexp(1.0, std::max(e - bits, least));
}

/// b(x): 2 ulps of x's largest coordinate; rounding each coordinate of a point of the mesh moves
/// it less than sqrt(3)/2 of that ulp.
double closest_bound(const Vec3<double>& x, bool float32) {
  return 2 * std::max({ulp_at(x.x, float32), ulp_at(x.y, float32), ulp_at(x.z, float32)});
}

}  // namespace

struct DistanceJudge::State {
  std::string name;
  std::vector<std::array<Vec3<double>, 3>> triangles;  // for the exact ties of answered triangles
  ExactMesh mesh;
  explicit State(const ContainsMesh& m)
      : name(m.name),
        mesh(VertexArray(reinterpret_cast<const double*>(m.vertices.data()), m.vertices.size()),
             IndexArray{m.triangles.empty() ? nullptr : m.triangles.data()->data(), m.triangles.size()}) {
    triangles.reserve(m.triangles.size());
    for (const auto& t : m.triangles) triangles.push_back({m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]});
  }
};

DistanceJudge::DistanceJudge(const ContainsMesh& mesh) : state_(std::make_unique<State>(mesh)) {}
DistanceJudge::~DistanceJudge() = default;
DistanceJudge::DistanceJudge(DistanceJudge&&) noexcept = default;
DistanceJudge& DistanceJudge::operator=(DistanceJudge&&) noexcept = default;

DistanceTally DistanceJudge::judge(const ContainsPoints& points, std::span<const DistanceAnswer> answers,
                                   const DistanceCheckOptions& opt) const {
  const std::size_t n = points.points.size();
  if (answers.size() != n || points.set.size() != n)
    throw std::invalid_argument(fmt::format("judge: {} answers for {} points", answers.size(), n));
  const State& s = *state_;
  DistanceTally tally;
  tally.signed_distance = opt.signed_distance;
  tally.precision = opt.precision;
  const bool float32 = opt.precision == ContainsPrecision::float32;
  tally.rel_tol = opt.rel_tol;
  tally.notes = points.notes;
  // answered: the answers' closest points' own distances to the mesh, where searched; near: x is
  // within b(x) of the exact nearest triangle (so of the mesh: not off it), the mesh not searched
  std::vector<ClosestPoint> ref(n), baseline(n), answered(n);
  std::vector<unsigned char> near(n, 0);
  KindQuota quota(opt.reproducers);
  auto exact_of = [&](std::size_t i) { return opt.signed_distance ? ref[i].signed_distance() : ref[i].distance; };
  // extra: the reproducer's tail, or a function making it (called only for a kept reproducer)
  auto finding = [&](std::uint64_t DistanceCounts::*counter, const char* kind, std::size_t i, const auto& extra) {
    ++(tally.*counter);
    ++tally.sets[points.set[i]].findings;
    if (!quota.keep(kind)) return;
    std::string tail;
    if constexpr (std::is_invocable_v<decltype(extra)>) tail = extra();
    else tail = extra;
    const Vec3<double>& p = points.points[i];
    const std::string exact = finite(p) ? fmt::format("{} (triangle {}{})", num(exact_of(i)), ref[i].triangle,
                                                      opt.signed_distance ? std::string(", ") + to_string(ref[i].side) : "")
                                        : std::string("invalid");
    tally.reproducers.push_back(
        {kind, i,
         fmt::format("{} set={} mesh={} point {} {} {} exact: {} answer: {}{}", kind, points.names[points.set[i]],
                     s.name, num(p.x), num(p.y), num(p.z), exact,
                     answers[i].failed ? std::string("failed") : num(answers[i].distance), tail)});
  };

  auto judge_distance_ulps = [&](std::size_t i, double d, double exact) {
    const std::uint64_t ulps = float32 ? ulp_distance(static_cast<float>(d), static_cast<float>(exact))
                                       : ulp_distance(d, exact);
    tally.max_ulps = std::max(tally.max_ulps, ulps);
    if (exact != 0 && std::isfinite(exact))
      tally.max_rel_error = std::max(tally.max_rel_error, std::fabs(d - exact) / std::fabs(exact));
    if (ulps <= 1) return;
    ++tally.over_1ulp;
    if (!(std::fabs(d - exact) <= opt.rel_tol * std::fabs(exact)))
      finding(&DistanceCounts::over_tolerance, "over-tolerance", i,
              fmt::format(" ({} ulps{})", ulps, float32 ? " of float" : ""));
  };

  auto judge_point = [&](std::size_t i) {
    const DistanceAnswer& a = answers[i];
    ++tally.points;
    if (!finite(points.points[i])) {
      ++tally.invalid_points;
      if (a.failed) finding(&DistanceCounts::invalid_failures, "invalid-point-failure", i, "");
      else if (!std::isnan(a.distance)) finding(&DistanceCounts::invalid_number, "invalid-point-number", i, "");
      return;
    }
    const double exact = exact_of(i);
    const bool on_surface = ref[i].distance == 0;
    if (on_surface) ++tally.surface;
    if (a.failed) return finding(&DistanceCounts::failures, "failure", i, "");
    const double d = a.distance;
    if (std::isnan(d) || (!opt.signed_distance && d < 0)) return finding(&DistanceCounts::garbage, "garbage", i, "");
    if (on_surface && d != 0) finding(&DistanceCounts::surface_nonzero, "surface-nonzero", i, "");
    if (opt.signed_distance && d != 0 && exact != 0 && (d < 0) != (exact < 0))
      finding(&DistanceCounts::wrong_sign, "wrong-sign", i, "");
    judge_distance_ulps(i, d, exact);
  };
  // The closest point and triangle answered at a valid point whose answer did not fail.
  auto judge_columns = [&](std::size_t i) {
    const DistanceAnswer& a = answers[i];
    if (a.failed || !finite(points.points[i])) return;
    const Vec3<double>& p = points.points[i];
    if (a.has_point) {
      ++tally.closest_points;
      const Vec3<double>& x = a.point;
      if (!finite(x)) {
        finding(&DistanceCounts::closest_off_mesh, "closest-off-mesh", i, fmt::format(" closest {}", exact_point(x)));
      } else {
        const double b = closest_bound(x, float32);
        if (!near[i] && answered[i].distance > b)
          finding(&DistanceCounts::closest_off_mesh, "closest-off-mesh", i,
                  fmt::format(" closest {} ({} from the mesh, bound {})", exact_point(x), num(answered[i].distance), num(b)));
        double from_p = detail::rounded_point_distance(p, x);  // NaN: the filter cannot tell
        if (std::isnan(from_p)) from_p = exact_triangle_distance(p, {x, x, x});
        if (from_p - ref[i].distance > b)
          finding(&DistanceCounts::closest_not_nearest, "closest-not-nearest", i,
                  fmt::format(" closest {} ({} from the point, bound {})", exact_point(x), num(from_p), num(b)));
      }
    }
    if (a.has_triangle) {
      ++tally.triangle_ids;
      const bool known = a.triangle >= 0 && static_cast<std::uint64_t>(a.triangle) < s.triangles.size();
      // The exact nearest triangle itself is among the ties without a comparison; another one where
      // the filter finds their nearest points on a corner or edge they share, else compared exactly.
      const bool nearest = known && ref[i].triangle != ClosestPoint::kNoTriangle &&
                           static_cast<std::uint64_t>(a.triangle) == ref[i].triangle;
      if (!nearest && (!known || ref[i].triangle == ClosestPoint::kNoTriangle ||
                       (!detail::certainly_tied(p, s.triangles[static_cast<std::size_t>(a.triangle)], s.triangles[ref[i].triangle]) &&
                        compare_triangle_distances(p, s.triangles[static_cast<std::size_t>(a.triangle)],
                                                   s.triangles[ref[i].triangle]) != 0)))
        finding(&DistanceCounts::wrong_triangle, "wrong-triangle", i, [&] {
          return known ? fmt::format(" triangle {} (exact distance {})", a.triangle,
                                     num(exact_triangle_distance(p, s.triangles[static_cast<std::size_t>(a.triangle)])))
                       : fmt::format(" triangle {} (no such triangle)", a.triangle);
        });
    }
  };
  for (std::size_t k = 0; k < points.names.size(); ++k) tally.sets.push_back({points.names[k], 0, 0, 0, 0});
  {  // Warm-up, untimed: the first call builds the distance tree.
    const std::size_t m = std::min<std::size_t>(n, 64);
    s.mesh.closest_points(std::span<const Vec3<double>>(points.points).first(m), std::span(baseline).first(m),
                          opt.signed_distance, 1);
  }
  const auto points_of = [&](std::size_t b, std::size_t e) {
    return std::span<const Vec3<double>>(points.points).subspan(b, e - b);
  };
  std::tie(tally.judge_seconds, tally.closest_seconds) = time_by_set(
      points.set, tally.sets,
      [&](std::size_t b, std::size_t e) {
        s.mesh.closest_points(points_of(b, e), std::span(ref).subspan(b, e - b), opt.signed_distance, opt.threads);
        // The answered closest points' own exact distances to the mesh, where needed: x within b(x) of
        // the exact nearest triangle is within b(x) of the mesh (the rounding is monotone), else the
        // mesh is searched. Within b(x) is decided by the filter where it can tell, else exactly.
        std::vector<Vec3<double>> xs;
        std::vector<std::size_t> at;
        for (std::size_t i = b; i < e; ++i) {
          const DistanceAnswer& a = answers[i];
          if (!a.has_point || a.failed || !finite(a.point) || !finite(points.points[i])) continue;
          if (ref[i].triangle != ClosestPoint::kNoTriangle) {
            const std::array<Vec3<double>, 3>& t = s.triangles[ref[i].triangle];
            const double bound = closest_bound(a.point, float32);
            if (detail::certainly_within(a.point, t, bound) || exact_triangle_distance(a.point, t) <= bound) {
              near[i] = 1;
              continue;
            }
          }
          xs.push_back(a.point), at.push_back(i);
        }
        std::vector<ClosestPoint> xd(xs.size());
        s.mesh.closest_points(xs, xd, false, opt.threads);
        for (std::size_t k = 0; k < xs.size(); ++k) answered[at[k]] = xd[k];
        for (std::size_t i = b; i < e; ++i) {
          ++tally.sets[points.set[i]].points;
          judge_point(i);
          judge_columns(i);
        }
      },
      [&](std::size_t b, std::size_t e) {
        s.mesh.closest_points(points_of(b, e), std::span(baseline).subspan(b, e - b), opt.signed_distance, opt.threads);
      });
  return tally;
}

std::vector<Vec3<double>> float_vertices(std::span<const Vec3<double>> vertices) {
  std::vector<Vec3<double>> out;
  out.reserve(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const Vec3<double>& v = vertices[i];
    const Vec3<double> f{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
    if (finite(v) && !finite(f))
      throw std::invalid_argument(fmt::format("vertex {} ({}) is beyond float's range: a float32 function cannot hold "
                                              "this mesh",
                                              i, exact_point(v)));
    out.push_back(f);
  }
  return out;
}

ContainsPoints distance_points(const ContainsMesh& mesh, const DistanceCheckOptions& opt) {
  ContainsCheckOptions c;
  c.precision = opt.precision;
  c.random_points = opt.random_points;
  c.max_points_per_set = opt.max_points_per_set;
  c.seed = opt.seed;
  c.sets = opt.sets;
  return contains_points(mesh, c);
}

void run_distance(const DistanceFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<DistanceAnswer> out, std::string& error) {
  if (out.size() != points.size()) throw std::invalid_argument("run_distance: output size differs from point count");
  std::vector<double> d;
  run_in_batches(
      points.size(), batch, error,
      [&](std::size_t at, std::size_t n) {
        d.assign(n, kNaN<double>);
        fn(points.subspan(at, n), d);
      },
      [&](std::size_t at, std::size_t n, bool failed) {
        for (std::size_t k = 0; k < n; ++k) out[at + k] = {.distance = d[k], .failed = failed};
      });
}

void run_distance(const DistanceAnswerFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<DistanceAnswer> out, std::string& error) {
  if (out.size() != points.size()) throw std::invalid_argument("run_distance: output size differs from point count");
  run_in_batches(
      points.size(), batch, error,
      [&](std::size_t at, std::size_t n) {
        const std::span<DistanceAnswer> batch_out = out.subspan(at, n);
        std::fill(batch_out.begin(), batch_out.end(), DistanceAnswer{});
        fn(points.subspan(at, n), batch_out);
      },
      [&](std::size_t at, std::size_t n, bool failed) {
        for (std::size_t k = 0; k < n; ++k) out[at + k].failed = failed;
      });
}

namespace {

/// The function run on the points and judged; under float32 on the mesh rounded to float, the
/// user's points (`user`) rounded to float; else on distance_points.
template <class Function>
DistanceTally run_and_judge(const Function& fn, const ContainsMesh& given, const std::vector<Vec3<double>>* user,
                            const DistanceCheckOptions& opt) {
  const bool float32 = opt.precision == ContainsPrecision::float32;
  const std::vector<Vec3<double>> rounded = float32 ? float_vertices(given.vertices) : std::vector<Vec3<double>>();
  const ContainsMesh mesh{float32 ? std::span<const Vec3<double>>(rounded) : given.vertices, given.triangles, given.name};
  ContainsPoints points;
  if (user) {
    for (const Vec3<double>& p : *user)
      points.points.push_back(float32 ? Vec3<double>{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)}
                                      : p);
    points.set.assign(points.points.size(), 0);
    points.names = {"user"};
  } else {
    points = distance_points(mesh, opt);
  }
  const DistanceJudge judge(mesh);
  std::vector<DistanceAnswer> answers(points.points.size());
  std::string error;
  run_distance(fn, points.points, opt.batch, answers, error);
  DistanceTally tally = judge.judge(points, answers, opt);
  if (!error.empty()) tally.notes.push_back("the function threw: " + error);
  return tally;
}

}  // namespace

DistanceTally check_distance(const DistanceFunction& fn, const ContainsMesh& mesh, const DistanceCheckOptions& opt) {
  return run_and_judge(fn, mesh, nullptr, opt);
}

DistanceTally check_distance(const DistanceFunction& fn, const ContainsMesh& mesh,
                             std::span<const Vec3<double>> user_points, const DistanceCheckOptions& opt) {
  const std::vector<Vec3<double>> user(user_points.begin(), user_points.end());
  return run_and_judge(fn, mesh, &user, opt);
}

DistanceTally check_distance(const DistanceAnswerFunction& fn, const ContainsMesh& mesh, const DistanceCheckOptions& opt) {
  return run_and_judge(fn, mesh, nullptr, opt);
}

DistanceTally check_distance(const DistanceAnswerFunction& fn, const ContainsMesh& mesh,
                             std::span<const Vec3<double>> user_points, const DistanceCheckOptions& opt) {
  const std::vector<Vec3<double>> user(user_points.begin(), user_points.end());
  return run_and_judge(fn, mesh, &user, opt);
}

std::string summary_text(const DistanceTally& tally) {
  return fmt::format("{:<18} {}{}{}\n", "distance", tally.signed_distance ? "signed" : "unsigned",
                     tally.precision == ContainsPrecision::float32 ? ", float (float ulps, the mesh rounded to float)" : "",
                     tally.rel_tol > 0 ? fmt::format(", rel_tol {}", tally.rel_tol) : std::string()) +
         counters_text(kDistanceCounters, tally, 18, [](const auto&) { return true; }) +
         fmt::format("{:<18} {:.3g}\n", "max_rel_error", tally.max_rel_error) +
         cost_text(tally.sets, "points", "closest_points", tally.judge_seconds, tally.closest_seconds) +
         notes_text(tally.notes, tally.reproducers);
}

}  // namespace rayproof::verify
