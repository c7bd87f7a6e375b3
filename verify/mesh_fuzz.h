#pragma once
/// Mesh-level property fuzzing (`rayproof fuzz --mesh`): random closed meshes, random interior
/// points, and two properties a watertight method must keep on every one of them.
///  - No leaks: a ray from an interior point aimed at any vertex or edge midpoint (direction the
///    exact difference, and the same direction normalized in float) has a closest hit.
///  - Parity: a ray from an interior point in a random direction, or aimed at a random point of a
///    random edge, crosses the closed surface an odd number of times. Hits at equal t are one
///    crossing, and so are edge or vertex contacts within a relative 1e-5 in t (the triangles
///    around an edge compute t separately); rays whose reference classes (the exact classes of
///    `certified`) show an edge, vertex or coplanar contact are set aside.
/// Meshes: perturbed icospheres (each vertex moved radially by a factor in [0.7, 1.3]: star-shaped
/// about the centre, closed) and convex hulls of random point sets (CGAL's convex_hull_3; the point
/// sets mix random doubles, spheres and small integer grids, whose hulls have coplanar facets).
/// Every vertex and interior point is a float, so float methods see the same mesh. Mesh i of seed s
/// is the same on every machine (CGAL's hull is put in a canonical order).
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "scene/accel.h"

namespace rayproof::verify {

enum class MeshShape { star, hull };

/// A perturbed icosphere (subdivided `subdivisions` times) scaled and moved at random, with
/// `count` interior points near its centre.
[[nodiscard]] mesh::Mesh random_star_mesh(std::mt19937_64& rng, int subdivisions, int count,
                                          std::vector<Vec3<double>>& interior);
/// The convex hull of `points` random points (at least 4 faces, closed), with `count` interior
/// points (random convex combinations of all hull vertices, checked strictly inside exactly).
[[nodiscard]] mesh::Mesh random_hull_mesh(std::mt19937_64& rng, int points, int count,
                                          std::vector<Vec3<double>>& interior);

struct MeshFuzzOptions {
  std::vector<scene::SceneMethod> methods;
  std::string reference = "certified";  ///< the method whose classes set contact rays aside
  double seconds = 0;                   ///< stop after this long (at a mesh boundary); 0: use max_meshes
  std::size_t max_meshes = 0;
  std::uint64_t seed = 1;
  int max_subdivisions = 2;   ///< icospheres have 20 .. 20 * 4^this triangles
  int max_hull_points = 96;   ///< hulls of 8 .. this many random points
  int interior_points = 2;    ///< per mesh
  int parity_rays = 32;       ///< random directions per interior point
  int threads = 1;
  std::size_t keep_findings = 20;  ///< per method
};

struct MeshFuzzStats {
  std::string method;
  std::uint64_t leak_rays = 0, leaks = 0;
  std::uint64_t parity_rays = 0, parity_failures = 0;
};

struct MeshFuzzFinding {
  std::string method;
  bool leak = true;  ///< leak (no closest hit), else parity (`crossings` is even)
  std::size_t mesh = 0;
  MeshShape shape = MeshShape::star;
  Ray<double> ray;
  std::size_t crossings = 0;
};

struct MeshFuzzResult {
  std::size_t meshes = 0, star_meshes = 0, hull_meshes = 0, triangles = 0;
  std::uint64_t contact_rays_set_aside = 0;  ///< parity rays with an exact edge/vertex contact
  double seconds = 0;
  std::vector<MeshFuzzStats> stats;  ///< in the order of the options' methods
  std::vector<MeshFuzzFinding> findings;
};

/// Mesh i of the campaign `opt` describes (seed, sizes, interior points), as run_mesh_fuzz draws
/// it; `rng` is left where the campaign goes on drawing (its parity rays).
[[nodiscard]] mesh::Mesh fuzz_mesh(const MeshFuzzOptions& opt, std::size_t i, MeshShape& shape,
                                   std::vector<Vec3<double>>& interior, std::mt19937_64& rng);

[[nodiscard]] MeshFuzzResult run_mesh_fuzz(const MeshFuzzOptions& opt);

}  // namespace rayproof::verify
