#pragma once
/// What `rayproof bench` prints: the throughput table, the builds, and the targets (speed against
/// Embree, two-thread scaling, build time, bytes per triangle, leaks) with a verdict each. Kept apart from the command so that a test can build them from known numbers;
/// every verdict is decided on the number as printed beside it.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "scene/compare/scene_bench.h"

namespace rayproof::cli {

using scene::compare::BenchBuild;
using scene::compare::BenchIsa;
using scene::compare::BenchRow;

enum class Goal { at_least, at_most };

/// One target (bench_targets) checked on one measurement: the value and goal as printed, and the verdict
/// ("met" or "missed by D (P% of the goal)") decided on the printed value.
struct BenchTarget {
  std::string mesh, what, rays, query;  ///< rays and query empty when the target is not per ray set
  std::string value, goal;
  bool met = false;
  std::string verdict;
};

/// The target `what` with `value` printed to `decimals` places against `goal` (at least or at most).
[[nodiscard]] BenchTarget check_target(const std::string& mesh, const std::string& what, const std::string& rays,
                                       const std::string& query, double value, double goal, Goal kind, int decimals);

/// The two-thread speed-up target (>= 1.9), not judged when the printed value is above 2.10: two
/// threads cannot do more than twice one thread's work, so such a value means a disturbed timing.
[[nodiscard]] BenchTarget scaling_target(const std::string& mesh, const std::string& what, const std::string& rays,
                                         const std::string& query, double speedup);

/// Every target the rows and builds allow: per mesh, ray set, query and path, robust / embree-robust
/// >= 1.0, certified / embree-robust >= 0.8, float / embree >= 1.0 (each against the competitor's
/// row on the same path; a packet path's target names it: "robust / embree-robust (packet8, 1
/// thread)") and, measured on two threads for single rays,
/// robust, certified and float two-thread speed-up >= 1.9; per mesh and thread count, build / Embree's
/// build <= 1.0; per mesh, robust's bytes per triangle <= 64 and robust's and certified's leaks = 0.
[[nodiscard]] std::vector<BenchTarget> bench_targets(const std::vector<BenchRow>& rows,
                                                     const std::vector<BenchBuild>& builds);

/// "isa: rayproof nodes <nodes>, leaves <leaves> (cpu: avx2 fma, no avx512f)\n" and, when
/// competitors report theirs, "isa: embree avx512, embree-avx2 avx2 (<how>: embree
/// <kernel>, embree-avx2 <kernel>)\n" (one parenthesis per way of knowing). Empty without ours.
[[nodiscard]] std::string isa_lines(const BenchIsa& isa);

/// For every Embree competitor on a max_isa=avx2 device ("embree-avx2", "embree-robust-avx2")
/// beside its default-device twin ("embree", "embree-robust"), one line per mesh, ray set and query:
/// "bunny00.off primary closest: embree-avx2 / embree 15.321 / 16.596 = 0.92 (single), ..." over
/// the paths both have, the rates (Mrays/s, one thread) as bench_table prints them and the ratio
/// of those printed rates. Empty when no such pair has rows.
[[nodiscard]] std::string avx2_ratio_lines(const std::vector<BenchRow>& rows);

/// The throughput table: one row per mesh, method, ray set, query and path, with the ratio to
/// embree-robust on the same mesh, rays, query and path (one thread each).
[[nodiscard]] std::string bench_table(const std::vector<BenchRow>& rows);
[[nodiscard]] std::string build_table(const std::vector<BenchBuild>& builds);
[[nodiscard]] std::string targets_table(const std::vector<BenchTarget>& targets);
/// A JSON array: the rows (fields of the earlier bench plus query, path, mesh and the scaling),
/// then one object per target ("target", "mesh", "rays", "query", "value", "goal", "met", "verdict"),
/// then, with `isa`, one object {"isa": {"rayproof": {"nodes", "leaves", "cpu": {feature: bool}},
/// "competitors": [{"name", "isa", "kernel", "how"}]}}.
[[nodiscard]] std::string bench_json(const std::vector<BenchRow>& rows, const std::vector<BenchTarget>& targets,
                                     const BenchIsa* isa = nullptr);

/// `bench contains --open`'s line on the first batch of `points` points on an open mesh (the one
/// that may tabulate the caps' field): "the first batch took 0.160 s, 0.100 s more than the best
/// batch after it (0.060 s at 0.3333 Mpoints/s)", the best batch's time computed from its rate as
/// printed; "..., no more than the best batch after it (...)" when it was not slower. Empty when
/// the best rate is not positive.
[[nodiscard]] std::string first_batch_line(double first_s, std::size_t points, double best_mpts);

}  // namespace rayproof::cli
