#pragma once
/// Someone else's all-hits function (every crossing of a ray with a mesh, as a list of hits)
/// judged exactly: the judgement of `rayproof check --crossings` and of Python's
/// rayproof.check_crossings (link rayproof::caster_check: CGAL, GMP, MPFR, TBB).
///
///   auto mine = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
///                   std::span<std::vector<verify::CrossingHit>> hits) { ... };  // per ray: (t, triangle)...
///   const verify::CrossingsTally tally = verify::check_crossings(mine, {vertices, triangles});
///
/// The function answers, per ray o + t d, every point at t > 0 where the ray passes through the
/// surface: a list of hits (t, triangle number), in increasing t. The reference is rayproof's
/// ExactMesh::ray_crossings (docs/contains.md, "Crossings"): each crossing once (a point where k
/// sheets pass the same way gives k crossings), with the touches apart (silhouette edges and
/// vertices, coincident triangles of opposite orientation, triangles whose plane holds the ray).
///
/// Matching is exact, never a window on t: a hit belongs to the contact (a crossing or a touch)
/// at which its triangle meets the ray, decided by the certified class of that triangle and, where
/// two contacts lie within two ulps, by an exact comparison of that triangle's t with the
/// contact's (GMP rationals). A crossing through an edge or a vertex involves every triangle that
/// meets the ray there: any of them may name it. Then, per contact: a crossing point of k
/// crossings wants k hits (fewer: `missing`, more: `duplicates`); a touch wants none (one or more:
/// one `touch_hits`, the others `duplicates`); a triangle that holds the ray is a touch of its own.
/// A hit's t is judged against the contact's exact t correctly rounded (to double, then to float
/// for a float engine), in ulps of the engine's precision: more than `max_ulps` is a finding.
/// Contacts at exact t = 0 (an origin on the surface) are neither wanted nor findings.
///
/// Ray sets: the caster judge's (caster_rays: leak, graze, face, surface, random, extreme,
/// invalid). For a float engine (precision float32) every ray is rounded to float and judged as
/// rounded; the mesh is judged as given.
///
/// Thread safety: the function is called from the calling thread only, batch by batch; the
/// judgement runs on TBB threads. Bad mesh arrays throw MeshInputError.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rayproof/verify/caster_check.h"
#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/judge_counters.h"

namespace rayproof::verify {

/// One hit of an all-hits answer: t along the ray, the triangle's number (its position in the
/// triangle array).
struct CrossingHit {
  double t = 0;
  std::int64_t triangle = -1;
};

/// crossings(origins, directions, hits_out): hits_out[i] (empty on entry) gets ray i's hits.
using CrossingsFunction = std::function<void(std::span<const Vec3<double>>, std::span<const Vec3<double>>,
                                             std::span<std::vector<CrossingHit>>)>;

struct CrossingsCheckOptions {
  CasterPrecision precision = CasterPrecision::float64;  ///< the ulps t errors are counted in
  std::uint64_t max_ulps = 1;             ///< t error allowed, in ulps of the precision
  std::size_t random_rays = 2000;
  std::size_t max_rays_per_set = 5000;    ///< larger sets are subsampled (evenly, deterministic)
  std::uint64_t seed = 1;
  std::vector<std::string> sets;          ///< empty: every set (caster_rays' names)
  std::size_t batch = 4096;               ///< rays per call of the function
  std::size_t reproducers = 5;            ///< kept per kind of finding
  int threads = 0;                        ///< judgement threads (0: TBB's default)
};

/// A function's answer to one ray.
struct CrossingsAnswer {
  std::vector<CrossingHit> hits;
  bool failed = false;  ///< the function threw (or its process died) on this ray's batch
};

/// The counts of a judgement (what each one counts: kCrossingsCounters).
struct CrossingsCounts {
  std::uint64_t rays = 0, crossings = 0, hits = 0;
  std::uint64_t missing = 0, duplicates = 0, touch_hits = 0, no_contact = 0, garbage = 0, wrong_order = 0;
  std::uint64_t t_over_tolerance = 0, max_ulps = 0, at_origin = 0, failures = 0;
  std::uint64_t invalid_rays = 0, invalid_hit = 0, invalid_failures = 0;
  /// Every counted finding: the sum of the counters marked `finding`.
  [[nodiscard]] constexpr std::uint64_t findings() const;
};

/// One counter of a CrossingsTally: its name, meaning and use, written down once (text, JSON and
/// Python's dict are made from kCrossingsCounters, in order; rayproof/verify/judge_counters.h).
using CrossingsCounter = JudgeCounter<CrossingsCounts>;

inline constexpr CrossingsCounter kCrossingsCounters[] = {
    {.key = "rays", .member = &CrossingsCounts::rays, .meaning = "judged (every ray given)"},
    {.key = "crossings",
     .member = &CrossingsCounts::crossings,
     .meaning = "exact crossings at t > 0 of the valid rays (each once; k sheets through one point: k)"},
    {.key = "hits", .member = &CrossingsCounts::hits, .meaning = "hits answered to valid rays"},
    {.key = "missing",
     .member = &CrossingsCounts::missing,
     .finding = true,
     .meaning = "an exact crossing with no hit at it (a crossing point of k crossings with h < k hits: k - h)"},
    {.key = "duplicates",
     .member = &CrossingsCounts::duplicates,
     .finding = true,
     .meaning = "a hit beyond those a contact wants: a crossing reported twice (e.g. by both triangles of a "
                "shared edge), or a touch reported more than once"},
    {.key = "touch_hits",
     .member = &CrossingsCounts::touch_hits,
     .finding = true,
     .meaning = "a touch reported as a crossing: a silhouette edge or vertex, coincident triangles of opposite "
                "orientation, a triangle whose plane holds the ray (once per touch)"},
    {.key = "no_contact",
     .member = &CrossingsCounts::no_contact,
     .finding = true,
     .meaning = "a hit on a triangle the ray does not meet at t > 0"},
    {.key = "garbage",
     .member = &CrossingsCounts::garbage,
     .finding = true,
     .meaning = "a hit that is none: t NaN or infinite, or a triangle number out of range"},
    {.key = "wrong_order",
     .member = &CrossingsCounts::wrong_order,
     .finding = true,
     .meaning = "a valid ray whose hits are not in increasing t (some t less than the one before)"},
    {.key = "t_over_tolerance",
     .member = &CrossingsCounts::t_over_tolerance,
     .finding = true,
     .meaning = "a hit at a crossing, t more than max_ulps (of the precision) from the exact t correctly rounded"},
    {.key = "max_ulps",
     .member = &CrossingsCounts::max_ulps,
     .maximum = true,
     .meaning = "the largest t error in ulps over the hits at crossings"},
    {.key = "at_origin",
     .member = &CrossingsCounts::at_origin,
     .meaning = "a hit on a triangle the ray meets at exact t = 0 (an origin on the surface: not judged)"},
    {.key = "failures",
     .member = &CrossingsCounts::failures,
     .finding = true,
     .meaning = "none on a valid ray: the function threw (or crashed, hung, wrote an unreadable line)"},
    {.key = "invalid_rays",
     .member = &CrossingsCounts::invalid_rays,
     .meaning = "a ray with a NaN or infinite component, or d = 0: it has no crossing"},
    {.key = "invalid_hit",
     .member = &CrossingsCounts::invalid_hit,
     .finding = true,
     .meaning = "an invalid ray answered with one or more hits"},
    {.key = "invalid_failures",
     .member = &CrossingsCounts::invalid_failures,
     .finding = true,
     .meaning = "none on an invalid ray: the function failed (it must not throw or crash on them)"},
    {.key = "findings", .meaning = "every counted finding: the sum of the counts above marked as findings"},
};

constexpr std::uint64_t CrossingsCounts::findings() const { return sum_of_findings(kCrossingsCounters, *this); }

/// Every counter of CrossingsCounts is in kCrossingsCounters once, and `findings` once.
constexpr bool every_crossings_counter_once_in_table() { return every_counter_once(kCrossingsCounters); }
static_assert(every_crossings_counter_once_in_table());

/// What check_crossings and CrossingsJudge::judge find.
struct CrossingsTally : CrossingsCounts {
  CasterPrecision precision = CasterPrecision::float64;
  std::uint64_t tolerance_ulps = 1;
  std::uint64_t rays_with_findings = 0;  ///< rays with one finding or more (a ray may have several)
  std::vector<ContainsSetCounts> sets;  ///< per ray set: rays (in `points`), findings, the cost
  std::vector<CasterReproducer> reproducers;
  std::vector<std::string> notes;
  double judge_seconds = 0;      ///< the judgement (the reference and the matching; the function excluded)
  double crossings_seconds = 0;  ///< rayproof's ExactMesh::ray_crossings on the same rays, timed in the same run
};

/// The exact reference on a mesh, built once; judge() may be called many times.
class CrossingsJudge {
 public:
  explicit CrossingsJudge(const CasterMesh& mesh);
  ~CrossingsJudge();
  CrossingsJudge(CrossingsJudge&&) noexcept;
  CrossingsJudge& operator=(CrossingsJudge&&) noexcept;
  /// Judges answers[i] to rays.rays[i] (sizes must match; std::invalid_argument otherwise).
  [[nodiscard]] CrossingsTally judge(const CasterRays& rays, std::span<const CrossingsAnswer> answers,
                                     const CrossingsCheckOptions& opt = {}) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The ray sets of a crossings judgement: caster_rays with the options' counts, sets and precision.
[[nodiscard]] CasterRays crossings_rays(const CasterMesh& mesh, const CrossingsCheckOptions& opt = {});

/// crossings_rays, the function called batch by batch (an exception fails that batch), judge.
[[nodiscard]] CrossingsTally check_crossings(const CrossingsFunction& fn, const CasterMesh& mesh,
                                             const CrossingsCheckOptions& opt = {});
/// The same on rays you give (the `set` of every ray "user").
[[nodiscard]] CrossingsTally check_crossings(const CrossingsFunction& fn, const CasterMesh& mesh,
                                             std::span<const Ray<double>> rays, const CrossingsCheckOptions& opt = {});

/// Runs the function on the rays batch by batch: an exception marks the batch's rays failed.
void run_crossings(const CrossingsFunction& fn, std::span<const Ray<double>> rays, std::size_t batch,
                   std::span<CrossingsAnswer> out, std::string& error);

/// The counts as text, per-set lines with their cost ratio, then the reproducers.
[[nodiscard]] std::string summary_text(const CrossingsTally& tally);

}  // namespace rayproof::verify
