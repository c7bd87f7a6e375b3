#pragma once
/// A whole ray caster (BVH, traversal, leaf test: yours or a library's) judged exactly on a mesh:
/// the judgement of `rayproof check --caster` and of Python's rayproof.check_caster (link
/// rayproof::caster_check: CGAL, GMP, MPFR, TBB).
///
///   auto mine = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
///                   std::span<double> t, std::span<std::int64_t> tri) { ... };  // miss: inf, -1
///   const verify::CasterTally tally = verify::check_caster(mine, {vertices, triangles});
///   if (tally.findings()) for (const auto& r : tally.reproducers) std::cout << r.line << '\n';
///
/// The caster answers, for each ray o + t d, its closest crossing with the mesh: t and the
/// triangle's number (its position in the triangle array), or t = inf and -1 for a miss. Optionally
/// (`any`) it answers occlusion: whether the ray crosses anything. Crossings count at t > 0.
///
/// The reference is exact: rayproof's certified MeshCaster (exact class, conservative traversal)
/// gives the first crossing; exact per-triangle tests (rayproof/verify/exact.h, t correctly
/// rounded) decide whether the caster's triangle is crossed, at what t, and ties. The judgement is
/// a CasterTally: one count per kind of answer (kCasterCounters below says what each one counts),
/// counts per ray set, and one-line reproducers (the first `reproducers` of each kind, by ray).
/// A ray whose first contact is coplanar is not judged on t; a ray whose origin lies on the
/// caster's triangle (exact t = 0) is right with t = 0 only.
///
/// Ray sets (caster_rays): `leak` rays from interior points of closed meshes through every vertex
/// and edge midpoint; `graze` rays along random view directions through silhouette edges; `face`
/// rays lying in triangles' planes; `surface` rays starting on triangles (centroids, vertices);
/// `random` rays; `extreme` rays with huge and tiny coordinates; `invalid` rays. For a float caster
/// (precision float32) every ray is rounded to float (a component beyond float's range becomes
/// infinite: an invalid ray) and judged as rounded; the mesh is judged as given.
///
/// Thread safety: the caster is called from the calling thread only, batch by batch; the judgement
/// runs on TBB threads. Bad mesh arrays throw MeshInputError (rayproof/scene/mesh_caster.h).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rayproof/ray.h"
#include "rayproof/verify/judge_counters.h"
#include "rayproof/vec3.h"

namespace rayproof::verify {

/// closest(origins, directions, t_out, triangle_out): one answer per ray (miss: inf and -1).
using ClosestCaster = std::function<void(std::span<const Vec3<double>>, std::span<const Vec3<double>>,
                                         std::span<double>, std::span<std::int64_t>)>;
/// any(origins, directions, occluded_out): 1 when the ray crosses the mesh at t > 0.
using AnyCaster =
    std::function<void(std::span<const Vec3<double>>, std::span<const Vec3<double>>, std::span<std::uint8_t>)>;

struct CasterMesh {
  std::span<const Vec3<double>> vertices;
  std::span<const std::array<std::uint32_t, 3>> triangles;
  std::string name = "mesh";  ///< shown in reproducers
};

enum class CasterPrecision : std::uint8_t { float32, float64 };

struct CasterCheckOptions {
  CasterPrecision precision = CasterPrecision::float64;  ///< the ulps t errors are counted in
  std::size_t random_rays = 2000;
  std::size_t max_rays_per_set = 20000;  ///< larger sets are subsampled (evenly, deterministic)
  std::uint64_t seed = 1;
  std::vector<std::string> sets;          ///< empty: every set
  std::size_t batch = 4096;               ///< rays per call of the caster
  std::size_t reproducers = 5;            ///< kept per kind of finding
  int threads = 0;                        ///< judgement threads (0: TBB's default)
};

/// A caster's answer to one ray.
struct CasterAnswer {
  double t = 0;
  std::int64_t triangle = -1;
  bool failed = false;   ///< the caster threw (or its process died) on this ray's batch
  std::int8_t any = -1;  ///< occlusion answer: 0, 1, or -1 when not asked
};

struct CasterRays {
  std::vector<Ray<double>> rays;
  std::vector<std::uint8_t> set;      ///< index into names
  std::vector<std::string> names;     ///< set names
  std::vector<std::string> notes;     ///< e.g. why a set is empty
};

struct CasterReproducer {
  std::string kind;  ///< "false-miss", "wrong-triangle", "t-error", ...
  std::size_t ray = 0;
  std::string line;  ///< one line: kind, set, mesh, ray, exact answer, caster answer
};

struct CasterSetCounts {
  std::string set;
  std::size_t rays = 0, findings = 0, false_miss = 0;
};

/// The counts of a judgement (what each one counts: kCasterCounters).
struct CasterCounts {
  std::uint64_t rays = 0, hits = 0;
  std::uint64_t false_miss = 0, coplanar_miss = 0, false_hit = 0, wrong_triangle = 0, wrong_triangle_near = 0;
  std::uint64_t t_over_1ulp = 0, max_ulps = 0;
  std::uint64_t garbage = 0, caster_failures = 0;
  std::uint64_t any_rays = 0, any_false_miss = 0, any_false_hit = 0, any_coplanar_miss = 0;
  std::uint64_t invalid_rays = 0, invalid_hit = 0, invalid_failures = 0;
  /// Every counted finding: the sum of the counters marked `finding` (coplanar misses and t errors
  /// within 1 ulp are not findings).
  [[nodiscard]] constexpr std::uint64_t findings() const;
};

/// One counter of a CasterTally: the one place its name, meaning and use are written down. The
/// summary text, `rayproof check --caster --json`, the report's columns and Python's dict are made
/// from kCasterCounters, in its order (rayproof/verify/judge_counters.h).
using CasterCounter = JudgeCounter<CasterCounts>;

inline constexpr CasterCounter kCasterCounters[] = {
    {.key = "rays", .member = &CasterCounts::rays, .meaning = "judged (every ray given)"},
    {.key = "hits",
     .member = &CasterCounts::hits,
     .meaning = "an answer (not a failure) to a valid ray that has an exact crossing at t > 0"},
    {.key = "false_miss",
     .member = &CasterCounts::false_miss,
     .finding = true,
     .meaning = "a miss, where the ray crosses the mesh (its first contact not coplanar)"},
    {.key = "coplanar_miss",
     .member = &CasterCounts::coplanar_miss,
     .meaning = "a miss, where the first contact is a ray lying in a triangle's plane (not a finding: many "
                "engines treat such rays as misses by design)"},
    {.key = "false_hit",
     .member = &CasterCounts::false_hit,
     .finding = true,
     .meaning = "a hit, where the ray crosses nothing at t > 0"},
    {.key = "wrong_triangle",
     .member = &CasterCounts::wrong_triangle,
     .finding = true,
     .meaning = "a triangle not crossed, or crossed farther than the first crossing (ties, triangles whose exact t "
                "rounds to the same double, are all right)"},
    {.key = "wrong_triangle_within_1ulp",
     .member = &CasterCounts::wrong_triangle_near,
     .text_label = "  within_1ulp",
     .column_label = "of them within 1 ulp",
     .meaning = "of the wrong triangles, those crossed within 1 ulp (of the caster's precision) of the first "
                "crossing: near ties a caster of that precision cannot order"},
    {.key = "t_over_1ulp",
     .member = &CasterCounts::t_over_1ulp,
     .finding = true,
     .meaning = "the right (or a tied) triangle, t more than 1 ulp of the caster's precision from the exact t "
                "(rounded to double, then to float for a float caster)"},
    {.key = "max_ulps",
     .member = &CasterCounts::max_ulps,
     .maximum = true,
     .meaning = "the largest t error in ulps over the rays judged on t"},
    {.key = "garbage",
     .member = &CasterCounts::garbage,
     .finding = true,
     .meaning = "not a miss nor a hit: t NaN, a triangle out of range, a finite t with triangle -1, a hit with "
                "t < 0 or infinite"},
    {.key = "caster_failures",
     .member = &CasterCounts::caster_failures,
     .finding = true,
     .meaning = "none: the caster threw (or crashed, hung, wrote an unreadable line) on the ray's batch"},
    {.key = "any_rays",
     .member = &CasterCounts::any_rays,
     .occlusion = true,
     .report_column = false,
     .meaning = "judged on an occlusion answer"},
    {.key = "any_false_miss",
     .member = &CasterCounts::any_false_miss,
     .finding = true,
     .occlusion = true,
     .report_column = false,
     .meaning = "occlusion 0, where the ray crosses the mesh (its first contact not coplanar)"},
    {.key = "any_false_hit",
     .member = &CasterCounts::any_false_hit,
     .finding = true,
     .occlusion = true,
     .report_column = false,
     .meaning = "occlusion 1, where the ray touches nothing at t >= 0"},
    {.key = "any_coplanar_miss",
     .member = &CasterCounts::any_coplanar_miss,
     .occlusion = true,
     .report_column = false,
     .meaning = "occlusion 0, where the first contact is coplanar (not a finding)"},
    {.key = "invalid_rays",
     .member = &CasterCounts::invalid_rays,
     .report_column = false,
     .meaning = "a ray with a NaN or infinite component, or d = 0: it has no crossing"},
    {.key = "invalid_hit",
     .member = &CasterCounts::invalid_hit,
     .finding = true,
     .meaning = "an answer other than a miss (triangle -1), or occlusion 1, to an invalid ray"},
    {.key = "invalid_failures",
     .member = &CasterCounts::invalid_failures,
     .finding = true,
     .meaning = "none on an invalid ray: the caster failed (it must not throw on them)"},
    {.key = "findings", .meaning = "every counted finding: the sum of the counts above marked as findings"},
};

constexpr std::uint64_t CasterCounts::findings() const { return sum_of_findings(kCasterCounters, *this); }

/// Every counter of CasterCounts is in kCasterCounters once, and `findings` (no member) once: a
/// counter added to the struct and not to the table does not compile.
constexpr bool every_counter_once_in_table() { return every_counter_once(kCasterCounters); }
static_assert(every_counter_once_in_table());

/// Whether the summary text and JSON show the counter (occlusion counts only when asked).
[[nodiscard]] constexpr bool shown(const CasterCounts& counts, const CasterCounter& counter) {
  return !counter.occlusion || counts.any_rays > 0;
}

/// What check_caster and CasterJudge::judge find: the counts, per ray set, with reproducers.
struct CasterTally : CasterCounts {
  std::vector<CasterSetCounts> sets;
  std::vector<CasterReproducer> reproducers;
  std::vector<std::string> notes;
};

/// CasterTally's name in 0.1, kept for one release (to go after 0.2): the type holds a tally, it
/// does not check anything.
using CasterCheck [[deprecated("verify::CasterCheck is now verify::CasterTally")]] = CasterTally;

/// The ray sets for a mesh (deterministic for the options).
[[nodiscard]] CasterRays caster_rays(const CasterMesh& mesh, const CasterCheckOptions& opt = {});

/// The exact reference on a mesh, built once; judge() may be called for many ray batches.
class CasterJudge {
 public:
  explicit CasterJudge(const CasterMesh& mesh);
  ~CasterJudge();
  CasterJudge(CasterJudge&&) noexcept;
  CasterJudge& operator=(CasterJudge&&) noexcept;
  /// Judges answers[i] to rays.rays[i] (sizes must match; std::invalid_argument otherwise).
  [[nodiscard]] CasterTally judge(const CasterRays& rays, std::span<const CasterAnswer> answers,
                                  const CasterCheckOptions& opt = {}) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// caster_rays, the caster called batch by batch (an exception fails that batch's rays), judge.
[[nodiscard]] CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh,
                                       const CasterCheckOptions& opt = {}, const AnyCaster& any = {});
/// The same on rays you give (the `set` of every ray "user").
[[nodiscard]] CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh,
                                       std::span<const Ray<double>> rays, const CasterCheckOptions& opt = {},
                                       const AnyCaster& any = {});

/// Runs the caster on the rays batch by batch: an exception marks the batch's rays failed and
/// keeps its message in `error` (the first one).
void run_caster(const ClosestCaster& closest, const AnyCaster& any, std::span<const Ray<double>> rays,
                std::size_t batch, std::span<CasterAnswer> out, std::string& error);

/// The counts as text, one `name value` per line, then the reproducers.
[[nodiscard]] std::string summary_text(const CasterTally& tally);

}  // namespace rayproof::verify
