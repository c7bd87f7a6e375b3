// `rayproof bench`'s measurements on one scene: Mrays/s of closest and any hit per method and
// competitor on primary and random rays (one thread, and `threads` for the speed-up), the packet
// paths, leaks on closed meshes, and the BVH builds beside Embree's. The tool prints and judges
// them (src/cli/bench_text.h); tests and other callers use the same numbers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "scene/accel.h"
#include "scene/scene.h"

namespace rayproof::scene::compare {

/// One method or competitor on one mesh, ray set, query and path: "single" (one ray at a time),
/// "packet8" / "packet16" (8 / 16 consecutive rays per call; primary rays in 4x2 pixel tiles).
struct BenchRow {
  std::string mesh, method, rays, query = "closest", path = "single";
  std::size_t n = 0;            ///< rays timed
  double mrays = 0;             ///< million rays per second on one thread
  int scaled_threads = 0;       ///< 0: not measured on more threads
  double mrays_scaled = 0;      ///< on scaled_threads threads
  double build_s = 0, bytes = -1;  ///< bytes per triangle the method reads: -1 not known
  double bytes_held = -1;          ///< bytes per triangle its structures hold: -1 not known
  std::int64_t leaks = -1, leak_rays = 0;  ///< leaks -1: not measured (not a closed mesh)
};

/// The BVH build on one mesh at one thread count: ours (scene::Accel, SAH) and Embree's (the
/// faster of its default and robust builds; -1 without Embree), each the best of some repeats.
struct BenchBuild {
  std::string mesh;
  int threads = 1;
  double ours_s = 0, embree_s = -1;
};

/// Which instruction set each side ran: ours (scene::compare::our_isa) and each competitor that
/// reports one (scene::compare::Competitor::isa; Embree's as Embree itself reports it).
struct BenchIsa {
  std::string nodes, leaves;                      ///< ours: "avx2-8wide" / "sse-4wide"; "avx2", "sse", ...
  std::vector<std::pair<std::string, bool>> cpu;  ///< CPU features and whether it has each
  struct Side {
    std::string name, isa, kernel, how;  ///< a competitor, its ISA, the kernel named, how it is known
  };
  std::vector<Side> competitors;
};

/// What to measure: the generated mesh's size, the ray counts, the competitors' names, how many
/// timed runs per measurement (the least is kept) and the primary rays' image.
struct SceneBenchOptions {
  std::size_t rays = 200000, slow_rays = 5000, leak_rays = 200000;
  std::string competitors = "embree,embree-robust,cgal-epick,cgal-epeck";
  int repeat = 3;
  int width = 640, height = 480;  ///< primary rays: this image of the default view (scenes without a camera)
  /// Also each compiled method through the scene BVH twice, on our binary tree and on Embree's
  /// (rtcBuildBVH, embree_build.h), both collapsed and traversed by rayproof: "NAME @ our tree" and
  /// "NAME @ embree tree" rows.
  bool embree_tree = false;
};

/// Runs every method (`methods`: the names as the user gave them, resolved by find_scene_method)
/// and competitor on the scene `s`, named `mesh_name` in the rows: appends rows (one thread, and
/// `threads` for the speed-up when above 1), builds (ours and Embree's at one thread and at
/// `threads`), notes (a packet path that answers otherwise than single rays; competitors' notes)
/// and the instruction sets to `isa`. Registry (non-compiled) methods run on `slow_rays` rays per set.
void bench_scene(const SceneBenchOptions& opt, const Scene& s, const std::string& mesh_name,
                 const std::vector<std::pair<std::string, SceneMethod>>& methods, int threads, std::vector<BenchRow>& rows,
                 std::vector<BenchBuild>& builds, std::vector<std::string>& notes, BenchIsa& isa);

}  // namespace rayproof::scene::compare
