// The judgement of someone else's distance function on a mesh (rayproof/verify/distance_check.h):
// ExactMesh::closest_points gives each point's correctly rounded exact distance (and its exact side
// for signed distances); the answers are counted against it in ulps and relatively.
#include "rayproof/verify/distance_check.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/mesh_caster.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

namespace {

std::string num(double x) { return exact_number(x); }

}  // namespace

struct DistanceJudge::State {
  std::string name;
  ExactMesh mesh;
  explicit State(const ContainsMesh& m)
      : name(m.name),
        mesh(VertexArray(reinterpret_cast<const double*>(m.vertices.data()), m.vertices.size()),
             IndexArray{m.triangles.empty() ? nullptr : m.triangles.data()->data(), m.triangles.size()}) {}
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
  tally.rel_tol = opt.rel_tol;
  tally.notes = points.notes;
  std::vector<ClosestPoint> ref(n), baseline(n);
  KindQuota quota(opt.reproducers);
  auto exact_of = [&](std::size_t i) { return opt.signed_distance ? ref[i].signed_distance() : ref[i].distance; };
  auto finding = [&](std::uint64_t DistanceCounts::*counter, const char* kind, std::size_t i, const std::string& extra) {
    ++(tally.*counter);
    ++tally.sets[points.set[i]].findings;
    if (!quota.keep(kind)) return;
    const Vec3<double>& p = points.points[i];
    const std::string exact = finite(p) ? fmt::format("{} (triangle {}{})", num(exact_of(i)), ref[i].triangle,
                                                      opt.signed_distance ? std::string(", ") + to_string(ref[i].side) : "")
                                        : std::string("invalid");
    tally.reproducers.push_back(
        {kind, i,
         fmt::format("{} set={} mesh={} point {} {} {} exact: {} answer: {}{}", kind, points.names[points.set[i]],
                     s.name, num(p.x), num(p.y), num(p.z), exact,
                     answers[i].failed ? std::string("failed") : num(answers[i].distance), extra)});
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
    const std::uint64_t ulps = ulp_distance(d, exact);
    tally.max_ulps = std::max(tally.max_ulps, ulps);
    if (exact != 0 && std::isfinite(exact))
      tally.max_rel_error = std::max(tally.max_rel_error, std::fabs(d - exact) / std::fabs(exact));
    if (ulps <= 1) return;
    ++tally.over_1ulp;
    if (!(std::fabs(d - exact) <= opt.rel_tol * std::fabs(exact)))
      finding(&DistanceCounts::over_tolerance, "over-tolerance", i, fmt::format(" ({} ulps)", ulps));
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
        for (std::size_t i = b; i < e; ++i) {
          ++tally.sets[points.set[i]].points;
          judge_point(i);
        }
      },
      [&](std::size_t b, std::size_t e) {
        s.mesh.closest_points(points_of(b, e), std::span(baseline).subspan(b, e - b), opt.signed_distance, opt.threads);
      });
  return tally;
}

ContainsPoints distance_points(const ContainsMesh& mesh, const DistanceCheckOptions& opt) {
  ContainsCheckOptions c;
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
        for (std::size_t k = 0; k < n; ++k) out[at + k] = {d[k], failed};
      });
}

namespace {

DistanceTally run_and_judge(const DistanceFunction& fn, const ContainsMesh& mesh, const ContainsPoints& points,
                            const DistanceCheckOptions& opt) {
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
  return run_and_judge(fn, mesh, distance_points(mesh, opt), opt);
}

DistanceTally check_distance(const DistanceFunction& fn, const ContainsMesh& mesh,
                             std::span<const Vec3<double>> user_points, const DistanceCheckOptions& opt) {
  ContainsPoints points;
  points.points.assign(user_points.begin(), user_points.end());
  points.set.assign(points.points.size(), 0);
  points.names = {"user"};
  return run_and_judge(fn, mesh, points, opt);
}

std::string summary_text(const DistanceTally& tally) {
  return fmt::format("{:<18} {}{}\n", "distance", tally.signed_distance ? "signed" : "unsigned",
                     tally.rel_tol > 0 ? fmt::format(", rel_tol {}", tally.rel_tol) : std::string()) +
         counters_text(kDistanceCounters, tally, 18, [](const auto&) { return true; }) +
         fmt::format("{:<18} {:.3g}\n", "max_rel_error", tally.max_rel_error) +
         cost_text(tally.sets, "points", "closest_points", tally.judge_seconds, tally.closest_seconds) +
         notes_text(tally.notes, tally.reproducers);
}

}  // namespace rayproof::verify
