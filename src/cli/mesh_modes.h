#pragma once
/// The options of check, fuzz and spawn, read by both halves of each command: the case-level
/// run (cmd_check.cpp, cmd_fuzz.cpp, cmd_spawn.cpp) and its --mesh mode, which traverses BVHs over
/// meshes (check_mesh.cpp, fuzz_mesh.cpp, spawn_mesh_cli.cpp).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cli/user_kernels.h"
#include "mesh/mesh.h"
#include "methods/method.h"

namespace rayproof::cli {

struct CheckCliOptions {
  UserKernelOptions user;
  std::string method;
  std::size_t count = 2000;
  std::uint64_t seed = 1;
  std::vector<std::string> families, expect, compare;
  std::optional<std::uint64_t> max_ulps;
  std::size_t reproducers = 3;
  std::string out;
  bool json = false;
  std::vector<std::string> mesh;  ///< mesh files, or `generated`
  std::size_t meshes = 8;         ///< how many generated meshes `generated` stands for
  std::size_t mesh_targets = 0;
  int interior = 2;
  bool plugin_in_process = false;
  std::string compare_plugin;  ///< --compare-plugin: the C build of an --opencl or --glsl kernel's formula
  std::vector<std::string> caster;       ///< --caster NAME=COMMAND: whole casters on --mesh (check_caster.cpp)
  std::string caster_precision = "double";
  double caster_timeout = 10;
  std::size_t caster_batch = 1024, caster_rays = 2000, caster_max_per_set = 20000;
  std::vector<std::string> caster_sets;
  std::vector<std::string> contains;  ///< --contains NAME=COMMAND: containment functions on --mesh (check_contains.cpp)
  std::string contains_rule = "automatic", contains_precision = "double";
  double contains_timeout = 10;
  std::size_t contains_batch = 1024, contains_points = 1000, contains_max_per_set = 1000;
  std::vector<std::string> contains_sets;
  std::string contains_scale = "1";  ///< --contains-scale: the mesh times this power of two (2^K)
  std::vector<std::string> distance;  ///< --distance NAME=COMMAND: distance functions on --mesh (check_distance.cpp)
  bool distance_signed = false;
  std::string distance_precision = "double";
  double distance_rel_tol = 0, distance_timeout = 10;
  std::size_t distance_batch = 1024, distance_points = 1000, distance_max_per_set = 1000;
  std::vector<std::string> distance_sets;
  std::string distance_scale = "1";  ///< --distance-scale: the mesh times this power of two (2^K)
  std::vector<std::string> crossings;  ///< --crossings NAME=COMMAND: all-hits functions on --mesh (check_crossings.cpp)
  std::string crossings_precision = "double";
  std::uint64_t crossings_max_ulps = 1;
  double crossings_timeout = 10;
  std::size_t crossings_batch = 1024, crossings_rays = 2000, crossings_max_per_set = 5000;
  std::vector<std::string> crossings_sets;
};


struct FuzzCliOptions {
  std::vector<std::string> methods, families;
  double seconds = 0;
  std::size_t cases = 0;
  std::uint64_t seed = 1;
  int jobs = 1;
  std::string out = "fuzz-findings";
  bool mesh = false;
  bool crossings = false;  ///< with mesh: fuzz ExactMesh::ray_crossings instead (fuzz_crossings.cpp)
  bool distance = false;  ///< fuzz --distance (fuzz_distance.cpp)
  bool winding = false;  ///< fuzz --winding (fuzz_winding.cpp)
  std::string shard;    ///< K/N
  std::string summary;  ///< write the summary as JSON here
  UserKernelOptions user;
  std::vector<std::string> merge_files;  ///< fuzz merge SUMMARY...
  double progress_seconds = 5;           ///< progress line interval when stderr is not a terminal
};


struct SpawnOptions {
  std::vector<std::string> kinds{"plane", "sphere", "disk"};
  std::vector<std::string> methods;
  std::vector<int> magnitudes{0, 20, 40};
  std::uint64_t trials = 20000;
  std::uint64_t seed = 1;
  double epsilon = 1e-4;
  double slab_gap = 0;  ///< > 0: count leaks through a slab of this relative thickness instead
  std::string mesh;     ///< a mesh file or "generated": count on triangle meshes instead
};

/// The mesh modes (check_mesh.cpp, fuzz_mesh.cpp, spawn_mesh_cli.cpp).
int run_mesh_check(const CheckCliOptions& o, const Method& kernel);
/// A mesh judged by check --caster or --contains: a file's, or one of fuzz --mesh's generated ones.
struct JudgedMesh {
  std::string name;
  mesh::Mesh mesh;
};
/// The meshes of --mesh (files, and `generated` as --meshes generated meshes of seed --seed), each
/// file's size noted on stderr; nothing (the error printed) when a file cannot be read.
std::optional<std::vector<JudgedMesh>> judged_meshes(const CheckCliOptions& o);
int run_caster_check(const CheckCliOptions& o);
int run_contains_check(const CheckCliOptions& o);
int run_distance_check(const CheckCliOptions& o);
/// check --crossings (check_crossings.cpp), and its options (registered on `check`).
int run_crossings_check(const CheckCliOptions& o);
void add_crossings_check_options(CLI::App& sub, CheckCliOptions& o);
int run_mesh_fuzz_cli(const FuzzCliOptions& o);
/// fuzz --distance: closest points against a brute force in rationals (verify/distance_fuzz.h).
int run_distance_fuzz_cli(const FuzzCliOptions& o);
int run_spawn_mesh(const SpawnOptions& opt);
/// fuzz --mesh --crossings (fuzz_crossings.cpp).
int run_crossings_fuzz_cli(const FuzzCliOptions& o);
/// fuzz --winding (fuzz_winding.cpp).
int run_winding_fuzz_cli(const FuzzCliOptions& o);

}  // namespace rayproof::cli
