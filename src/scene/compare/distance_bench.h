#pragma once
/// The measuring half of `rayproof bench distance`: the point sets, rayproof's closest points
/// beside the competitors of distance_compare.h (one thread, runs interleaved), and each method's
/// wrong triangles and distance errors against exact. The tool prints what these return.
#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/distance.h"

namespace rayproof::scene::compare {

/// A closest-point method as the bench times it.
struct DistanceMethod {
  std::string name;
  std::function<void(std::span<const Vec3<double>>, std::span<std::uint32_t>, std::span<double>)> run;
  /// Optional: the method's own batch call on every point at `threads` threads, as a user makes it
  /// (rayproof's closest_points); without it, more than one thread runs `run` on chunks of points.
  std::function<void(std::span<const Vec3<double>>, std::span<std::uint32_t>, std::span<double>, int threads)>
      run_threads{};
  std::vector<double> rates{};  ///< Mpoints/s per run
  std::vector<std::uint32_t> tri{};  ///< the last run's triangles
  std::vector<double> dist{};  ///< and distances
};

/// rayproof (closest_points without and with the side) first, then with `ablation` rayproof with one
/// part turned off per method (the same answers; rayproof/it is that part's speed-up), then the
/// competitors that can be built here; `notes` gets a line for each that cannot. `cm` must outlive
/// the methods.
[[nodiscard]] std::vector<DistanceMethod> distance_methods(const mesh::Mesh& m, const ExactMesh& cm,
                                                           std::vector<std::string>& notes, bool ablation = false);

/// The seconds the bench's set-up took: cm's distance tree (built by its first query) and
/// distance_methods (the competitors' structures).
struct DistanceBuilds {
  double tree_s = 0, methods_s = 0;
};
/// distance_methods after building cm's distance tree, both timed into `builds`.
[[nodiscard]] std::vector<DistanceMethod> timed_distance_methods(const mesh::Mesh& m, const ExactMesh& cm,
                                                                 std::vector<std::string>& notes, bool ablation,
                                                                 DistanceBuilds& builds);

/// The mesh of `bench distance`: a file, or for "generated" the 1.31M-triangle bumpy sphere
/// (scene::bumpy_sphere(2^20), as bench contains). Throws mesh::MeshError for a bad file.
[[nodiscard]] mesh::Mesh distance_bench_mesh(const std::string& path);

/// `n` points uniform in the box grown by 20%, and `n` near the surface (a random point of a random
/// triangle moved along its normal by up to 1e-3 of the box diagonal).
struct DistancePointSets {
  std::vector<Vec3<double>> uniform, near;
};
[[nodiscard]] DistancePointSets distance_point_sets(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng);

/// One point set measured: per method (in the order of `ms`) wrong triangles (not nearest,
/// exactly), distances off the exact distance correctly rounded and the largest ulp error; a check
/// of the reference on a sample; how often each of rayproof's stages decided (by DistanceStage).
struct DistanceSetResult {
  std::size_t points = 0;
  std::vector<std::size_t> wrong, off;
  std::vector<double> max_ulps;
  std::size_t sample = 0, sample_bad = 0;
  std::array<std::size_t, 5> stages{};
  std::size_t side_differ = 0;  ///< batch sides (closest_points with the side) that differ from contains(p)
};
/// Each method runs on `threads` threads (> 1: the points split into chunks run concurrently
/// through the method's own one-thread call, the same for every method).
[[nodiscard]] DistanceSetResult time_distance_set(const mesh::Mesh& m, const ExactMesh& cm, std::vector<DistanceMethod>& ms,
                                                  const std::vector<Vec3<double>>& pts, int repeat, int threads = 1);

}  // namespace rayproof::scene::compare
