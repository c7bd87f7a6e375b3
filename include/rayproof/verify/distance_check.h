#pragma once
/// Someone else's distance or signed distance function judged exactly on a mesh: the judgement of
/// `rayproof check --distance` and of Python's rayproof.check_distance (link rayproof::caster_check:
/// CGAL, GMP, MPFR, TBB).
///
///   auto mine = [&](std::span<const Vec3<double>> points, std::span<double> d) { ... };
///   const verify::DistanceTally tally = verify::check_distance(mine, {vertices, triangles});
///
/// The function answers, per point, the distance to the mesh (the union of its closed triangles),
/// or with `signed_distance` the signed distance (negative inside, 0 on the surface, positive
/// outside; the side as rayproof's contains gives it under the automatic rule). The reference is
/// rayproof's ExactMesh::closest_point: the exact distance correctly rounded (docs/distance.md).
/// Errors are counted in double ulps of the answer against that rounded exact value, and, against
/// the user's relative tolerance `rel_tol`, relatively: a finding is an answer more than 1 ulp off
/// and more than rel_tol * |exact| off (rel_tol 0: every answer more than 1 ulp off).
///
/// The points are the containment judge's sets (contains_points, rayproof/verify/contains_check.h):
/// surface points (exact distance 0), one ulp off them, thin parts, far, random and invalid points.
/// An invalid point (NaN or infinite coordinate) has no distance: NaN is the answer; a number there
/// is a finding (invalid_number), and so is a failure on one.
///
/// Closest points and triangles (optional, per answer): a function may answer, beside the
/// distance, the closest point x it found and its triangle's index. With b(x) = 2 ulps of x's
/// largest coordinate (a power of two; the ulps of the judged precision), x is judged as the
/// rounding of a point of the mesh: off the mesh when its correctly rounded exact distance to the
/// mesh exceeds b(x); not nearest when its correctly rounded distance to the query point exceeds
/// the correctly rounded exact distance by more than b(x) (the difference in double). The triangle
/// is wrong unless it is among the exact ties: the triangles at exactly the minimum distance.
///
/// Precision float32 (a float engine: Open3D, Embree): the mesh is rounded to float
/// (float_vertices: give it to the function, distance_points and DistanceJudge; check_distance
/// does), the points are made on it and rounded to float (contains_points' float32), and the
/// answers are judged against the exact answers on that float input, in float ulps.
///
/// Thread safety: the function is called from the calling thread only, batch by batch; the
/// judgement runs on TBB threads. Bad mesh arrays throw MeshInputError.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayproof/verify/contains_check.h"

namespace rayproof::verify {

/// distance(points, distance_out): one answer per point.
using DistanceFunction = std::function<void(std::span<const Vec3<double>>, std::span<double>)>;

struct DistanceCheckOptions {
  bool signed_distance = false;  ///< the function answers signed distances
  /// float32: points rounded to float, errors in float ulps (see the header's comment)
  ContainsPrecision precision = ContainsPrecision::float64;
  double rel_tol = 0;            ///< relative error allowed beyond 1 ulp (0: none)
  std::size_t random_points = 1000;
  std::size_t max_points_per_set = 1000;  ///< larger sets are subsampled (evenly, deterministic)
  std::uint64_t seed = 1;
  std::vector<std::string> sets;  ///< empty: every set (contains_points' names)
  std::size_t batch = 4096;       ///< points per call of the function
  std::size_t reproducers = 5;    ///< kept per kind of finding
  int threads = 0;                ///< judgement threads (0: TBB's default)
};

/// A function's answer to one point.
struct DistanceAnswer {
  double distance = std::numeric_limits<double>::quiet_NaN();
  Vec3<double> point{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::quiet_NaN()};  ///< the closest point, when has_point
  std::int64_t triangle = -1;  ///< the closest point's triangle (file order), when has_triangle
  bool has_point = false, has_triangle = false;
  bool failed = false;  ///< the function threw (or its process died) on this point's batch
};

/// distance(points, answers): one answer per point, its distance and optionally its closest point
/// and triangle (set has_point, has_triangle); `failed` is the judge's.
using DistanceAnswerFunction = std::function<void(std::span<const Vec3<double>>, std::span<DistanceAnswer>)>;

/// The counts of a judgement (what each one counts: kDistanceCounters).
struct DistanceCounts {
  std::uint64_t points = 0, surface = 0;
  std::uint64_t over_1ulp = 0, over_tolerance = 0, max_ulps = 0;
  std::uint64_t wrong_sign = 0, surface_nonzero = 0;
  std::uint64_t closest_points = 0, closest_off_mesh = 0, closest_not_nearest = 0;
  std::uint64_t triangle_ids = 0, wrong_triangle = 0;
  std::uint64_t garbage = 0, failures = 0;
  std::uint64_t invalid_points = 0, invalid_number = 0, invalid_failures = 0;
  /// Every counted finding: the sum of the counters marked `finding`.
  [[nodiscard]] constexpr std::uint64_t findings() const;
};

/// One counter of a DistanceTally: its name, meaning and use, written down once (text, JSON and
/// Python's dict are made from kDistanceCounters, in order; rayproof/verify/judge_counters.h).
using DistanceCounter = JudgeCounter<DistanceCounts>;

inline constexpr DistanceCounter kDistanceCounters[] = {
    {.key = "points", .member = &DistanceCounts::points, .meaning = "judged (every point given)"},
    {.key = "surface", .member = &DistanceCounts::surface, .meaning = "exactly on the surface: exact distance 0"},
    {.key = "over_1ulp",
     .member = &DistanceCounts::over_1ulp,
     .meaning = "a number more than 1 ulp (double; float under precision float32) from the correctly rounded exact "
                "(signed) distance"},
    {.key = "over_tolerance",
     .member = &DistanceCounts::over_tolerance,
     .finding = true,
     .meaning = "of them, more than rel_tol * |exact| off too (rel_tol 0: all of them)"},
    {.key = "max_ulps",
     .member = &DistanceCounts::max_ulps,
     .maximum = true,
     .meaning = "the largest error in ulps over the numbers answered at valid points"},
    {.key = "wrong_sign",
     .member = &DistanceCounts::wrong_sign,
     .finding = true,
     .meaning = "signed: a nonzero answer of the wrong sign (negative outside, positive inside)"},
    {.key = "surface_nonzero",
     .member = &DistanceCounts::surface_nonzero,
     .finding = true,
     .meaning = "a nonzero number at a surface point (exact distance 0)"},
    {.key = "closest_points",
     .member = &DistanceCounts::closest_points,
     .meaning = "a valid point answered (not failed) with a closest point x (judged below; b(x): 2 ulps of x's largest "
                "coordinate)"},
    {.key = "closest_off_mesh",
     .member = &DistanceCounts::closest_off_mesh,
     .finding = true,
     .meaning = "x farther than b(x) from every triangle (exact distance, correctly rounded), or not finite"},
    {.key = "closest_not_nearest",
     .member = &DistanceCounts::closest_not_nearest,
     .finding = true,
     .meaning = "x farther from the point than the exact distance plus b(x) (both correctly rounded)"},
    {.key = "triangle_ids",
     .member = &DistanceCounts::triangle_ids,
     .meaning = "a valid point answered (not failed) with a triangle id"},
    {.key = "wrong_triangle",
     .member = &DistanceCounts::wrong_triangle,
     .finding = true,
     .meaning = "a triangle id not among the exact ties (the triangles at exactly the exact distance)"},
    {.key = "garbage",
     .member = &DistanceCounts::garbage,
     .finding = true,
     .meaning = "no distance at a valid point: NaN, or a negative number when unsigned"},
    {.key = "failures",
     .member = &DistanceCounts::failures,
     .finding = true,
     .meaning = "none on a valid point: the function threw (or crashed, hung, wrote an unreadable line)"},
    {.key = "invalid_points",
     .member = &DistanceCounts::invalid_points,
     .meaning = "a point with a NaN or infinite coordinate: it has no distance (NaN is the answer)"},
    {.key = "invalid_number",
     .member = &DistanceCounts::invalid_number,
     .finding = true,
     .meaning = "a number (not NaN) answered at an invalid point"},
    {.key = "invalid_failures",
     .member = &DistanceCounts::invalid_failures,
     .finding = true,
     .meaning = "none on an invalid point: the function failed (it must not throw or crash on them)"},
    {.key = "findings", .meaning = "every counted finding: the sum of the counts above marked as findings"},
};

constexpr std::uint64_t DistanceCounts::findings() const { return sum_of_findings(kDistanceCounters, *this); }

/// Every counter of DistanceCounts is in kDistanceCounters once, and `findings` once.
constexpr bool every_distance_counter_once_in_table() { return every_counter_once(kDistanceCounters); }
static_assert(every_distance_counter_once_in_table());

/// What check_distance and DistanceJudge::judge find.
struct DistanceTally : DistanceCounts {
  bool signed_distance = false;
  ContainsPrecision precision = ContainsPrecision::float64;
  double rel_tol = 0;
  double max_rel_error = 0;  ///< the largest relative error over the numbers answered at valid, off-surface points
  std::vector<ContainsSetCounts> sets;  ///< points, findings and the cost per set
  std::vector<ContainsReproducer> reproducers;
  std::vector<std::string> notes;
  double judge_seconds = 0;     ///< the judgement (the reference and the tally; the function excluded)
  double closest_seconds = 0;   ///< rayproof's ExactMesh::closest_points on the same points, timed in the same run
};

/// The exact reference on a mesh, built once; judge() may be called many times.
class DistanceJudge {
 public:
  explicit DistanceJudge(const ContainsMesh& mesh);
  ~DistanceJudge();
  DistanceJudge(DistanceJudge&&) noexcept;
  DistanceJudge& operator=(DistanceJudge&&) noexcept;
  /// Judges answers[i] to points.points[i] (sizes must match; std::invalid_argument otherwise).
  [[nodiscard]] DistanceTally judge(const ContainsPoints& points, std::span<const DistanceAnswer> answers,
                                    const DistanceCheckOptions& opt = {}) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The vertices a float32 function holds: every coordinate rounded to float (std::invalid_argument
/// when one is beyond float's range).
[[nodiscard]] std::vector<Vec3<double>> float_vertices(std::span<const Vec3<double>> vertices);

/// The point sets of a distance judgement: contains_points with the options' counts and sets.
[[nodiscard]] ContainsPoints distance_points(const ContainsMesh& mesh, const DistanceCheckOptions& opt = {});

/// distance_points, the function called batch by batch (an exception fails that batch), judge.
[[nodiscard]] DistanceTally check_distance(const DistanceFunction& fn, const ContainsMesh& mesh,
                                           const DistanceCheckOptions& opt = {});
/// The same on points you give (the `set` of every point "user"; rounded to float under float32).
[[nodiscard]] DistanceTally check_distance(const DistanceFunction& fn, const ContainsMesh& mesh,
                                           std::span<const Vec3<double>> points, const DistanceCheckOptions& opt = {});
/// The same for a function answering closest points and triangles too.
[[nodiscard]] DistanceTally check_distance(const DistanceAnswerFunction& fn, const ContainsMesh& mesh,
                                           const DistanceCheckOptions& opt = {});
[[nodiscard]] DistanceTally check_distance(const DistanceAnswerFunction& fn, const ContainsMesh& mesh,
                                           std::span<const Vec3<double>> points, const DistanceCheckOptions& opt = {});

/// Runs the function on the points batch by batch: an exception marks the batch's points failed.
void run_distance(const DistanceFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<DistanceAnswer> out, std::string& error);
void run_distance(const DistanceAnswerFunction& fn, std::span<const Vec3<double>> points, std::size_t batch,
                  std::span<DistanceAnswer> out, std::string& error);

/// The counts as text, per-set lines with their cost ratio, then the reproducers.
[[nodiscard]] std::string summary_text(const DistanceTally& tally);

}  // namespace rayproof::verify
