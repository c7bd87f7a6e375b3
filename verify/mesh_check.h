#pragma once
/// Watertightness of one triangle kernel (a user's, or a built-in method) on closed meshes:
/// `rayproof check --mesh` and the user kernels of `fuzz --mesh`.
///
/// From interior points, rays aim at every vertex and every edge midpoint of a closed mesh (each
/// target twice: direction the exact difference, and that direction normalized in float), where a
/// kernel that is not watertight lets rays slip between triangles. A finder method that is exact in
/// class (`certified`) gives the ray's first crossing of the surface; rayproof's conservative BVH
/// traversal gives every triangle in a leaf the ray reaches before just past that crossing: the
/// candidates (none that the ray touches there is left out). The kernel answers every candidate case
/// (the ray against one triangle) in batches through Method::classify_many. A ray none of whose
/// candidates the kernel hits is a leak; it is kept with the candidates the ray touches at its first
/// crossing as case lines: the triangles it slipped between. For a float kernel, the finder works on
/// the float-rounded mesh and rays, what the kernel sees. A ray the finder sees cross nothing (the
/// point was not inside, or the mesh is not closed) is counted apart and never charged to the kernel.
#include <cstdint>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "methods/method.h"
#include "scene/accel.h"
#include "verify/mesh_fuzz.h"

namespace rayproof::verify {

struct MeshUnderTest {
  std::string name;  ///< a file name, or "generated #i (icosphere|hull)"
  mesh::Mesh mesh;
  std::vector<Vec3<double>> interior;  ///< strictly inside points (floats, so float kernels see the same rays)
};

/// One candidate triangle of a ray: the case the kernel answered and what the finder found.
struct Candidate {
  io::Case input;          ///< as the kernel saw it (float-rounded for float kernels)
  io::CaseResult answer;   ///< the kernel's answer
  Contact finder_contact = Contact::miss;  ///< the finder's class (exact for certified)
  double finder_t = 0;
};

struct MeshLeak {
  Ray<double> ray;
  std::vector<Candidate> candidates;  ///< the triangles it slipped between (touched at its first crossing)
  std::size_t candidate_count = 0;    ///< every candidate near the ray (all missed by the kernel)
};

struct MeshCheck {
  std::string mesh;
  std::size_t triangles = 0;
  std::uint64_t rays = 0, candidate_cases = 0, leaks = 0;
  std::uint64_t rays_without_candidates = 0;  ///< not charged to the kernel
  std::vector<MeshLeak> reproducers;          ///< the first `keep` leaks
  std::vector<KernelFailure> failures;
};

struct MeshCheckOptions {
  scene::SceneMethod finder;        ///< conservative traversal, class-exact for triangles: certified
  std::size_t max_targets = 0;      ///< vertices and edge midpoints per mesh, evenly strided (0: all)
  std::size_t batch = 8192;         ///< candidate cases per classify_many call
  std::size_t keep = 3;             ///< leaks kept per mesh as reproducers
};

/// Checks the kernel (it must answer triangles) on one mesh.
[[nodiscard]] MeshCheck check_mesh(const Method& kernel, const MeshUnderTest& m, const MeshCheckOptions& opt);

/// Why the mesh cannot be leak-checked ("12 edges are not shared by exactly two triangles"), or
/// nothing when it is closed: every edge shared by exactly two triangles, no degenerate index.
[[nodiscard]] std::optional<std::string> closed_mesh_problem(const mesh::Mesh& m);

/// Up to `count` points strictly inside a closed mesh, rounded to float: its volume centroid and
/// points just inside its triangles, each kept when `finder` sees an odd number of crossings and
/// no edge, vertex or coplanar contact on three rays from it. Deterministic for a seed.
[[nodiscard]] std::vector<Vec3<double>> interior_points(const mesh::Mesh& m, const scene::SceneMethod& finder,
                                                        int count, std::uint64_t seed);

/// The i-th generated mesh of a mesh fuzz campaign (verify/mesh_fuzz.h), with its interior points
/// and its name "generated #i (icosphere|hull)".
[[nodiscard]] MeshUnderTest generated_mesh(const MeshFuzzOptions& opt, std::size_t i);

}  // namespace rayproof::verify
