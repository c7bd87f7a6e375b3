// The judgement of someone else's containment function on a mesh (rayproof/verify/contains_check.h):
// rayproof's exact ExactMesh gives each point's side (on a closed oriented mesh its exact winding
// number, from which the nonzero, parity and winding rules all follow); only the disagreements
// under the winding rule cost more (their generalized winding number and its bound). The function is
// run, and the summary written, below too.
#include "rayproof/verify/contains_check.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/mesh_caster.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

namespace {

/// The exact answer at one point.
struct Reference {
  Side side = Side::invalid;       ///< under the rule judged
  bool rules_differ = false;       ///< nonzero and parity differ here (closed oriented meshes)
  bool near_half = false;          ///< winding rule: w within its double bound of 1/2 (computed on disagreements)
  std::int32_t winding = 0;        ///< the exact winding number (closed oriented meshes)
};

Side side_of(bool inside) { return inside ? Side::inside : Side::outside; }

std::string answer_text(const ContainsAnswer& a) {
  if (a.failed) return "failed";
  if (a.side == ContainsAnswer::kNotAnInteger) return "not-an-integer";
  return fmt::format("{}", a.side);
}

/// Whether an answer is one of 0, 1, 2.
bool readable(const ContainsAnswer& a) { return !a.failed && a.side >= 0 && a.side <= 2; }

/// Runs `body` over [begin, end) in chunks on `threads` TBB threads (0: TBB's default); serially
/// below 2048 points, as ExactMesh::contains does (its batches are the cost baseline).
template <class Body>
void parallel_range(std::size_t begin, std::size_t end, int threads, Body&& body) {
  if (end <= begin) return;
  if (threads == 1 || end - begin < 2048) return static_cast<void>(body(begin, end));
  auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, 1024),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  };
  if (threads > 0) tbb::task_arena(threads).execute(run);
  else run();
}

}  // namespace

struct ContainsJudge::State {
  std::string name;
  ExactMesh mesh;
  bool oriented = false;  ///< closed and oriented: the exact winding number decides every rule
  ContainsRule asked = ContainsRule::automatic;

  State(const ContainsMesh& m, ContainsRule rule)
      : name(m.name),
        mesh(VertexArray(reinterpret_cast<const double*>(m.vertices.data()), m.vertices.size()),
             IndexArray{m.triangles.empty() ? nullptr : m.triangles.data()->data(), m.triangles.size()}, rule),
        oriented(mesh.closed() && mesh.oriented()),
        asked(rule) {}

  /// The side of p under the rule `rule` from its exact winding number k (closed oriented meshes).
  [[nodiscard]] Side from_winding(std::int32_t k) const {
    if (k == ExactMesh::kOnSurface) return Side::surface;
    switch (mesh.rule()) {
      case ContainsRule::parity: return side_of((k & 1) != 0);
      case ContainsRule::winding: return side_of(k >= 1);
      default: return side_of(k != 0);
    }
  }

  /// Whether the generalized winding number at p cannot be separated from 1/2: its certified
  /// interval (winding_value) refined, while it holds 1/2, from a coarse bound down to the direct
  /// evaluation of every triangle, still holds 1/2. The coarse steps are what make a function that
  /// is wrong on many points affordable: most intervals leave 1/2 at once.
  [[nodiscard]] bool near_half(const Vec3<double>& p) const {
    for (double tolerance : {0x1p-3, 0x1p-12, 0.0}) {
      const WindingValue w = mesh.winding_value(p, tolerance);
      if (w.surface || !(std::fabs(w.w - 0.5) <= w.bound)) return false;
    }
    return true;
  }

  /// The references of points [b, e) into ref (the rule's sides; on closed oriented meshes the
  /// winding number and whether the rules differ).
  void reference(std::span<const Vec3<double>> points, std::size_t b, std::size_t e, std::vector<Reference>& ref,
                 std::vector<Side>& sides, int threads) const {
    if (oriented) {
      parallel_range(b, e, threads, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) {
          Reference& r = ref[i];
          if (!finite(points[i])) {
            r = {};
            continue;
          }
          r.winding = mesh.winding(points[i]);
          r.side = from_winding(r.winding);
          r.rules_differ = r.side != Side::surface && (r.winding != 0) != ((r.winding & 1) != 0);
        }
      });
      return;
    }
    mesh.contains(points.subspan(b, e - b), std::span<Side>(sides).subspan(b, e - b), threads);
    for (std::size_t i = b; i < e; ++i) ref[i] = {sides[i], false, false, 0};
  }
};

ContainsJudge::ContainsJudge(const ContainsMesh& mesh, ContainsRule rule)
    : state_(std::make_unique<State>(mesh, rule)) {}
ContainsJudge::~ContainsJudge() = default;
ContainsJudge::ContainsJudge(ContainsJudge&&) noexcept = default;
ContainsJudge& ContainsJudge::operator=(ContainsJudge&&) noexcept = default;
ContainsRule ContainsJudge::rule() const { return state_->mesh.rule(); }

ContainsTally ContainsJudge::judge(const ContainsPoints& points, std::span<const ContainsAnswer> answers,
                                   const ContainsCheckOptions& opt) const {
  const std::size_t n = points.points.size();
  if (answers.size() != n || points.set.size() != n)
    throw std::invalid_argument(fmt::format("judge: {} answers for {} points", answers.size(), n));
  const State& s = *state_;
  const bool winding_rule = s.mesh.rule() == ContainsRule::winding && !s.oriented;
  ContainsTally tally;
  tally.rule = s.mesh.rule();
  tally.notes = points.notes;
  std::vector<Reference> ref(n);
  std::vector<Side> sides(n), baseline(n);
  KindQuota quota(opt.reproducers);

  auto finding = [&](std::uint64_t ContainsCounts::*counter, const char* kind, std::size_t i, const std::string& exact) {
    ++(tally.*counter);
    ++tally.sets[points.set[i]].findings;
    if (!quota.keep(kind)) return;
    tally.reproducers.push_back({kind, i,
                                 fmt::format("{} set={} mesh={} point {} exact: {} answer: {}", kind,
                                             points.names[points.set[i]], s.name, exact_point(points.points[i]), exact,
                                             answer_text(answers[i]))});
  };
  auto exact_text = [&](std::size_t i) {
    std::string text = to_string(ref[i].side);
    if (s.oriented && ref[i].side != Side::surface && ref[i].side != Side::invalid)
      text += fmt::format(" (winding number {}, rule {})", ref[i].winding, to_string(s.mesh.rule()));
    else text += fmt::format(" (rule {})", to_string(s.mesh.rule()));
    return text;
  };

  /// One point's answer into the tally (its reference computed).
  auto judge_point = [&](std::size_t i) {
    const ContainsAnswer& a = answers[i];
    const Reference& r = ref[i];
    ++tally.points;
    if (r.side == Side::invalid) {
      ++tally.invalid_points;
      if (a.failed) finding(&ContainsCounts::invalid_failures, "invalid-point-failure", i, "invalid");
      else if (!readable(a)) finding(&ContainsCounts::garbage, "garbage", i, "invalid");
      else if (a.side == 1) ++tally.invalid_said_inside;
      else if (a.side == 2) ++tally.invalid_said_surface;
      return;
    }
    if (r.side == Side::inside) ++tally.inside;
    if (r.side == Side::surface) ++tally.surface;
    if (r.rules_differ) ++tally.rules_differ;
    if (a.failed) return finding(&ContainsCounts::failures, "failure", i, exact_text(i));
    if (!readable(a)) return finding(&ContainsCounts::garbage, "garbage", i, exact_text(i));
    if (r.side == Side::surface) {
      ++(a.side == 0 ? tally.surface_said_outside : a.side == 1 ? tally.surface_said_inside : tally.surface_said_surface);
      return;
    }
    if (a.side == 2) return finding(&ContainsCounts::false_surface, "false-surface", i, exact_text(i));
    const bool said_inside = a.side == 1, inside = r.side == Side::inside;
    if (said_inside == inside) return;
    if (r.rules_differ) {
      ++tally.rules_differ_other;
      if (s.asked == ContainsRule::automatic) return;
    }
    if (r.near_half) {
      ++tally.winding_near_half;
      return;
    }
    if (inside) finding(&ContainsCounts::inside_called_outside, "inside-called-outside", i, exact_text(i));
    else finding(&ContainsCounts::outside_called_inside, "outside-called-inside", i, exact_text(i));
  };

  // Set by set (the points of a set are consecutive; sets in order): the judgement timed, then
  // rayproof's own contains on the same points, timed alone.
  for (std::size_t k = 0; k < points.names.size(); ++k) tally.sets.push_back({points.names[k], 0, 0, 0, 0});
  {  // Warm-up, untimed: the first set timed should not pay for the tree's first touch alone.
    const std::size_t m = std::min<std::size_t>(n, 64);
    s.mesh.contains(std::span<const Vec3<double>>(points.points).first(m), std::span<Side>(baseline).first(m), 1);
  }
  std::tie(tally.judge_seconds, tally.contains_seconds) = time_by_set(
      points.set, tally.sets,
      [&](std::size_t b, std::size_t e) {
        s.reference(points.points, b, e, ref, sides, opt.threads);
        if (winding_rule)  // the disagreements' generalized winding numbers: near 1/2, or decided
          parallel_range(b, e, opt.threads, [&](std::size_t lo, std::size_t hi) {
            for (std::size_t i = lo; i < hi; ++i) {
              const ContainsAnswer& a = answers[i];
              const Side side = ref[i].side;
              if (!readable(a) || a.side == 2 || (side != Side::inside && side != Side::outside) ||
                  (a.side == 1) == (side == Side::inside))
                continue;
              ref[i].near_half = s.near_half(points.points[i]);
            }
          });
        for (std::size_t i = b; i < e; ++i) {
          ++tally.sets[points.set[i]].points;
          judge_point(i);
        }
      },
      [&](std::size_t b, std::size_t e) {
        s.mesh.contains(std::span<const Vec3<double>>(points.points).subspan(b, e - b),
                        std::span<Side>(baseline).subspan(b, e - b), opt.threads);
      });
  return tally;
}

void run_contains(const ContainsFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<ContainsAnswer> out, std::string& error) {
  if (out.size() != points.size()) throw std::invalid_argument("run_contains: output size differs from point count");
  std::vector<std::int32_t> side;
  run_in_batches(
      points.size(), batch, error,
      [&](std::size_t at, std::size_t n) {
        side.assign(n, -1);  // not written: garbage
        fn(points.subspan(at, n), side);
      },
      [&](std::size_t at, std::size_t n, bool failed) {
        for (std::size_t k = 0; k < n; ++k) out[at + k] = {side[k], failed};
      });
}

namespace {

ContainsTally run_and_judge(const ContainsFunction& fn, const ContainsMesh& mesh, const ContainsPoints& points,
                            const ContainsCheckOptions& opt) {
  const ContainsJudge judge(mesh, opt.rule);
  std::vector<ContainsAnswer> answers(points.points.size());
  std::string error;
  run_contains(fn, points.points, opt.batch, answers, error);
  ContainsTally tally = judge.judge(points, answers, opt);
  if (!error.empty()) tally.notes.push_back("the function threw: " + error);
  return tally;
}

}  // namespace

ContainsTally check_contains(const ContainsFunction& fn, const ContainsMesh& mesh, const ContainsCheckOptions& opt) {
  return run_and_judge(fn, mesh, contains_points(mesh, opt), opt);
}

ContainsTally check_contains(const ContainsFunction& fn, const ContainsMesh& mesh,
                             std::span<const Vec3<double>> user_points, const ContainsCheckOptions& opt) {
  ContainsPoints points;
  points.points.assign(user_points.begin(), user_points.end());
  points.set.assign(points.points.size(), 0);
  points.names = {"user"};
  return run_and_judge(fn, mesh, points, opt);
}

std::string summary_text(const ContainsTally& tally) {
  return fmt::format("{:<22} {}\n", "rule", to_string(tally.rule)) +
         counters_text(kContainsCounters, tally, 22, [](const auto&) { return true; }) +
         cost_text(tally.sets, "points", "contains", tally.judge_seconds, tally.contains_seconds) +
         notes_text(tally.notes, tally.reproducers);
}

}  // namespace rayproof::verify
