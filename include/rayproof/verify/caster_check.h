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
/// rounded) decide whether the caster's triangle is crossed, at what t, and ties. Per ray:
///  - false_miss      the ray crosses the mesh (first contact not coplanar); the caster answered a miss
///  - coplanar_miss   the first contact is a ray lying in a triangle's plane; the caster answered a
///                    miss (counted apart: many engines treat such rays as misses by design)
///  - false_hit       the ray crosses nothing at t > 0; the caster answered a hit
///  - wrong_triangle  the caster's triangle is not crossed, or crossed farther than the first
///                    crossing (ties, triangles whose exact t rounds to the same double, are all right);
///                    wrong_triangle_near counts those of them crossed within 1 ulp (of the caster's
///                    precision) of the first crossing: near ties a caster of that precision cannot order
///  - t_over_1ulp     right triangle (or a tied one), t more than 1 ulp from the exact t, in ulps of
///                    the caster's precision (exact t rounded to double, then to float for a float
///                    caster); max_ulps the largest such error. A ray whose first contact is coplanar
///                    is not judged on t. A ray whose origin lies on the caster's triangle (exact
///                    t = 0) is right with t = 0 only.
///  - garbage         an answer that is not a miss or a hit: t NaN, a triangle out of range, a
///                    finite t with triangle -1, a hit with t < 0 or infinite
///  - caster_failures the caster threw on the batch holding the ray (the run goes on)
///  - any_false_miss, any_false_hit, any_coplanar_miss: the same for the occlusion answers
///  - invalid rays (a NaN or infinite component, or d = 0) have no crossing: counted in
///    invalid_rays; a hit answered on one in invalid_hit (a finding), a failure in invalid_failures
///    (a finding: the caster must not throw on them).
/// Each finding keeps a one-line reproducer (the first `reproducers` of each kind, by ray).
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
#include <vector>

#include "rayproof/ray.h"
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

/// What check_caster and CasterJudge::judge find: the counts, per ray set, with reproducers.
struct CasterTally {
  std::size_t rays = 0, hits = 0;  ///< rays judged; rays with an exact crossing at t > 0
  std::size_t false_miss = 0, coplanar_miss = 0, false_hit = 0, wrong_triangle = 0, wrong_triangle_near = 0;
  std::size_t t_over_1ulp = 0;
  std::uint64_t max_ulps = 0;
  std::size_t garbage = 0, caster_failures = 0;
  std::size_t any_rays = 0, any_false_miss = 0, any_false_hit = 0, any_coplanar_miss = 0;
  std::size_t invalid_rays = 0, invalid_hit = 0, invalid_failures = 0;
  std::vector<CasterSetCounts> sets;
  std::vector<CasterReproducer> reproducers;
  std::vector<std::string> notes;
  /// Every counted finding (coplanar misses and t errors within 1 ulp are not findings).
  [[nodiscard]] std::size_t findings() const;
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
  std::unique_ptr<State> s_;
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
[[nodiscard]] std::string summary_text(const CasterTally& c);

}  // namespace rayproof::verify
