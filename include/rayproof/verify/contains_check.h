#pragma once
/// Someone else's inside/outside (containment) function judged exactly on a mesh: the judgement of
/// `rayproof check --contains` and of Python's rayproof.check_contains (link rayproof::caster_check:
/// CGAL, GMP, MPFR, TBB).
///
///   auto mine = [&](std::span<const Vec3<double>> points, std::span<std::int32_t> side) { ... };
///   const verify::ContainsTally tally = verify::check_contains(mine, {vertices, triangles});
///   if (tally.findings()) for (const auto& r : tally.reproducers) std::cout << r.line << '\n';
///
/// The function answers, per point, 0 (outside), 1 (inside) or, optionally, 2 (on the surface).
/// Any other value is garbage. The reference is rayproof's own exact containment
/// (rayproof::ExactMesh, rayproof/scene/contains.h, docs/contains.md) under the options' `rule`
/// (automatic by default, as `contains`): the exact side of each double point (surface: the point
/// lies on a closed triangle, exactly).
///
/// What is not an error, and is reported apart:
/// - at a point exactly on the surface any of 0, 1, 2 is right (counted by what was answered);
/// - on a closed oriented mesh, points where the nonzero and parity rules differ (an even nonzero
///   winding number: overlapping shells) are counted; under the automatic rule either rule's answer
///   is right there (the other rule's answer is counted in rules_differ_other); under a named rule
///   (nonzero, parity, winding) only that rule's answer is;
/// - under the winding rule (open meshes), an answer that differs from the exact one at a point whose
///   generalized winding number lies within the bound of its direct double evaluation of 1/2
///   (winding_near_half): a double-precision implementation cannot decide those;
/// - invalid points (a NaN or infinite coordinate) have no side: 0, 1 and 2 are all accepted there;
///   the function failing (throwing, crashing) on them is a finding (invalid_failures), and garbage
///   is garbage everywhere.
///
/// Point sets (contains_points): `vertex` (every vertex), `edge` (edge midpoints rounded to double),
/// `face` (triangle centroids rounded to double), `nudged` (those points moved one ulp both ways
/// along the summed normal of the triangles they lie on: every coordinate whose component is at
/// least a tenth of the largest), `medial` (near the medial axis: from the midpoints of edges
/// shared by triangles along the bisector of their normals, both ways, 2^-20, 2^-4 and 2^-1 of the
/// edge's length away, the offset rounded to 11 bits so that adding it is exact: where triangles
/// are (nearly) equally near; exact ties where the two faces mirror each other), `thin` (points
/// through and just beyond the thinnest parts, along triangles' normals), `far` (points from 10 to
/// 1e300 mesh sizes away), `random` (uniform in the mesh's box, enlarged by a tenth), `invalid`.
/// With precision float32 every point is rounded to float (a coordinate beyond float's range
/// becomes infinite: an invalid point) and nudged by one float ulp; the mesh is judged as given
/// (give a float function a mesh of floats).
///
/// Thread safety: the function is called from the calling thread only, batch by batch; the
/// judgement runs on TBB threads. Bad mesh arrays throw MeshInputError (rayproof/scene/mesh_caster.h);
/// a rule the mesh cannot take (nonzero or parity on a mesh that is not closed) throws
/// MeshNotClosedError (rayproof/scene/contains.h).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayproof/scene/contains.h"
#include "rayproof/vec3.h"
#include "rayproof/verify/judge_counters.h"

namespace rayproof::verify {

/// contains(points, side_out): one answer per point: 0 outside, 1 inside, 2 on the surface.
using ContainsFunction = std::function<void(std::span<const Vec3<double>>, std::span<std::int32_t>)>;

struct ContainsMesh {
  std::span<const Vec3<double>> vertices;
  std::span<const std::array<std::uint32_t, 3>> triangles;
  std::string name = "mesh";  ///< shown in reproducers
};

/// The precision of the function under test: a float32 function (Open3D's, Embree's) is given
/// points rounded to float (nudged one float ulp), and judged on them as rounded.
enum class ContainsPrecision : std::uint8_t { float32, float64 };

struct ContainsCheckOptions {
  ContainsRule rule = ContainsRule::automatic;  ///< the rule the answers are judged by
  ContainsPrecision precision = ContainsPrecision::float64;  ///< of the points made (contains_points)
  std::size_t random_points = 1000;
  std::size_t max_points_per_set = 1000;  ///< larger sets are subsampled (evenly, deterministic)
  std::uint64_t seed = 1;
  std::vector<std::string> sets;  ///< empty: every set
  std::size_t batch = 4096;       ///< points per call of the function
  std::size_t reproducers = 5;    ///< kept per kind of finding
  int threads = 0;                ///< judgement threads (0: TBB's default)
};

/// A function's answer to one point.
struct ContainsAnswer {
  /// An answer that is not an integer at all (NaN, 0.5 from Python) or beyond int32: garbage,
  /// printed as such in reproducers.
  static constexpr std::int32_t kNotAnInteger = std::numeric_limits<std::int32_t>::min();
  std::int32_t side = -1;  ///< 0, 1, 2; anything else is garbage
  bool failed = false;     ///< the function threw (or its process died) on this point's batch
};

struct ContainsPoints {
  std::vector<Vec3<double>> points;
  std::vector<std::uint8_t> set;   ///< index into names
  std::vector<std::string> names;  ///< set names
  std::vector<std::string> notes;  ///< e.g. why a set is empty
};

struct ContainsReproducer {
  std::string kind;  ///< "inside-called-outside", "garbage", ...
  std::size_t point = 0;
  std::string line;  ///< one line: kind, set, mesh, point (exact decimal), exact side, the answer
};

struct ContainsSetCounts {
  std::string set;
  std::size_t points = 0, findings = 0;
  double judge_seconds = 0, contains_seconds = 0;  ///< the judgement, and rayproof's contains alone, on this set
};

/// The counts of a judgement (what each one counts: kContainsCounters).
struct ContainsCounts {
  std::uint64_t points = 0, inside = 0, surface = 0;
  std::uint64_t inside_called_outside = 0, outside_called_inside = 0, false_surface = 0;
  std::uint64_t surface_said_outside = 0, surface_said_inside = 0, surface_said_surface = 0;
  std::uint64_t rules_differ = 0, rules_differ_other = 0, winding_near_half = 0;
  std::uint64_t garbage = 0, failures = 0;
  std::uint64_t invalid_points = 0, invalid_said_inside = 0, invalid_said_surface = 0, invalid_failures = 0;
  /// Every counted finding: the sum of the counters marked `finding`.
  [[nodiscard]] constexpr std::uint64_t findings() const;
};

/// One counter of a ContainsTally: its name, meaning and use, written down once. The summary text,
/// `rayproof check --contains --json` and Python's dict are made from kContainsCounters, in order
/// (rayproof/verify/judge_counters.h).
using ContainsCounter = JudgeCounter<ContainsCounts>;

inline constexpr ContainsCounter kContainsCounters[] = {
    {.key = "points", .member = &ContainsCounts::points, .meaning = "judged (every point given)"},
    {.key = "inside", .member = &ContainsCounts::inside, .meaning = "exactly inside under the rule judged"},
    {.key = "surface",
     .member = &ContainsCounts::surface,
     .meaning = "exactly on the surface (on a closed triangle of nonzero area)"},
    {.key = "inside_called_outside",
     .member = &ContainsCounts::inside_called_outside,
     .finding = true,
     .meaning = "answered 0 (outside) at a point exactly inside"},
    {.key = "outside_called_inside",
     .member = &ContainsCounts::outside_called_inside,
     .finding = true,
     .meaning = "answered 1 (inside) at a point exactly outside"},
    {.key = "false_surface",
     .member = &ContainsCounts::false_surface,
     .finding = true,
     .meaning = "answered 2 (surface) at a point exactly inside or outside"},
    {.key = "surface_said_outside",
     .member = &ContainsCounts::surface_said_outside,
     .meaning = "answered 0 at a surface point (not a finding)"},
    {.key = "surface_said_inside",
     .member = &ContainsCounts::surface_said_inside,
     .meaning = "answered 1 at a surface point (not a finding)"},
    {.key = "surface_said_surface",
     .member = &ContainsCounts::surface_said_surface,
     .meaning = "answered 2 at a surface point"},
    {.key = "rules_differ",
     .member = &ContainsCounts::rules_differ,
     .meaning = "points of a closed oriented mesh where the nonzero and parity rules differ (an even nonzero "
                "winding number)"},
    {.key = "rules_differ_other",
     .member = &ContainsCounts::rules_differ_other,
     .meaning = "of them, answered as the rule not judged: right under the automatic rule; under a named rule "
                "also counted in inside_called_outside or outside_called_inside"},
    {.key = "winding_near_half",
     .member = &ContainsCounts::winding_near_half,
     .meaning = "under the winding rule, an inside/outside answer other than the exact one where the generalized "
                "winding number lies within its double evaluation's bound of 1/2 (not a finding)"},
    {.key = "garbage",
     .member = &ContainsCounts::garbage,
     .finding = true,
     .meaning = "not 0, 1 or 2 (on any point)"},
    {.key = "failures",
     .member = &ContainsCounts::failures,
     .finding = true,
     .meaning = "none on a valid point: the function threw (or crashed, hung, wrote an unreadable line) on its batch"},
    {.key = "invalid_points",
     .member = &ContainsCounts::invalid_points,
     .meaning = "a point with a NaN or infinite coordinate: it has no side, and 0, 1 or 2 is accepted"},
    {.key = "invalid_said_inside",
     .member = &ContainsCounts::invalid_said_inside,
     .meaning = "answered 1 at an invalid point (not a finding)"},
    {.key = "invalid_said_surface",
     .member = &ContainsCounts::invalid_said_surface,
     .meaning = "answered 2 at an invalid point (not a finding)"},
    {.key = "invalid_failures",
     .member = &ContainsCounts::invalid_failures,
     .finding = true,
     .meaning = "none on an invalid point: the function failed (it must not throw or crash on them)"},
    {.key = "findings", .meaning = "every counted finding: the sum of the counts above marked as findings"},
};

constexpr std::uint64_t ContainsCounts::findings() const { return sum_of_findings(kContainsCounters, *this); }

/// Every counter of ContainsCounts is in kContainsCounters once, and `findings` once.
constexpr bool every_contains_counter_once_in_table() { return every_counter_once(kContainsCounters); }
static_assert(every_contains_counter_once_in_table());

/// What check_contains and ContainsJudge::judge find: the counts, per point set, with reproducers
/// and the judgement's cost beside rayproof's own contains on the same points.
struct ContainsTally : ContainsCounts {
  ContainsRule rule = ContainsRule::automatic;  ///< the rule that answered (automatic resolved)
  std::vector<ContainsSetCounts> sets;
  std::vector<ContainsReproducer> reproducers;
  std::vector<std::string> notes;
  double judge_seconds = 0;     ///< the judgement (the reference and the tally; the function excluded)
  double contains_seconds = 0;  ///< rayproof's ExactMesh::contains on the same points, timed in the same run
};

/// The point sets for a mesh (deterministic for the options). std::invalid_argument for an unknown set.
[[nodiscard]] ContainsPoints contains_points(const ContainsMesh& mesh, const ContainsCheckOptions& opt = {});

/// The exact reference on a mesh under a rule, built once; judge() may be called many times.
class ContainsJudge {
 public:
  ContainsJudge(const ContainsMesh& mesh, ContainsRule rule = ContainsRule::automatic);
  ~ContainsJudge();
  ContainsJudge(ContainsJudge&&) noexcept;
  ContainsJudge& operator=(ContainsJudge&&) noexcept;
  /// The rule that answers (automatic resolved: nonzero, parity or winding).
  [[nodiscard]] ContainsRule rule() const;
  /// Judges answers[i] to points.points[i] (sizes must match; std::invalid_argument otherwise).
  [[nodiscard]] ContainsTally judge(const ContainsPoints& points, std::span<const ContainsAnswer> answers,
                                    const ContainsCheckOptions& opt = {}) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// contains_points, the function called batch by batch (an exception fails that batch's points),
/// judge.
[[nodiscard]] ContainsTally check_contains(const ContainsFunction& fn, const ContainsMesh& mesh,
                                           const ContainsCheckOptions& opt = {});
/// The same on points you give (the `set` of every point "user").
[[nodiscard]] ContainsTally check_contains(const ContainsFunction& fn, const ContainsMesh& mesh,
                                           std::span<const Vec3<double>> points, const ContainsCheckOptions& opt = {});

/// Runs the function on the points batch by batch: an exception marks the batch's points failed
/// and keeps its message in `error` (the first one).
void run_contains(const ContainsFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<ContainsAnswer> out, std::string& error);

/// The counts as text, one `name value` per line, per-set lines with their cost ratio, then the
/// reproducers.
[[nodiscard]] std::string summary_text(const ContainsTally& tally);

}  // namespace rayproof::verify
