#pragma once
/// What a scene's geometry is made of, for `rayproof advise`: degenerate (zero area, decided
/// exactly) and sliver triangles, open and non-manifold edges, closed components, the magnitudes of
/// its coordinates, whether they are floats, and which analytic kinds it holds.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "scene/scene.h"

namespace rayproof::scene {

struct SceneAnalysis {
  std::size_t vertices = 0, triangles = 0;
  std::size_t spheres = 0, ellipsoids = 0, disks = 0, boxes = 0, lights = 0;
  bool has_camera = false;

  /// Triangles whose three vertices are collinear (or repeated), decided in exact arithmetic.
  std::size_t degenerate = 0;
  /// Triangles whose collinearity is not decided (collinear_exact: non-finite or hugely spread coordinates).
  std::size_t undecided = 0;
  /// Non-degenerate triangles whose aspect (longest edge squared over twice the area: the longest
  /// edge over the altitude onto it; 1.15 for an equilateral triangle) exceeds `sliver_aspect`.
  std::size_t slivers = 0;
  double sliver_aspect = 0;  ///< the threshold used
  double max_aspect = 0;     ///< the largest aspect among non-degenerate triangles (0: none)

  /// Vertices at the same position are one vertex for the topology below (meshes from STL files
  /// repeat them); `welded` is how many were merged.
  std::size_t welded = 0;
  std::size_t edges = 0;              ///< distinct edges (vertex pairs) of the triangles
  std::size_t open_edges = 0;         ///< edges of exactly one triangle
  std::size_t non_manifold_edges = 0; ///< edges of three or more triangles
  /// Connected components (triangles sharing an edge) and the closed ones: every edge of a closed
  /// component belongs to exactly two triangles.
  std::size_t components = 0, closed_components = 0;
  /// For each triangle its component number (0..components-1), and per component whether it is closed.
  std::vector<std::uint32_t> component_of;
  std::vector<bool> component_closed;

  /// Coordinates of the geometry (vertices; centres, radii, semi-axes and corners of analytic
  /// primitives): the smallest nonzero and the largest magnitude, and the spread in binades,
  /// ilogb(max) - ilogb(min) (0 when all are zero).
  double min_abs = 0, max_abs = 0;
  int spread_binades = 0;
  std::size_t zero_coordinates = 0, coordinates = 0;
  /// Vertices with a coordinate that is not a float (float(x) != x), and analytic parameters likewise.
  std::size_t non_float_vertices = 0, non_float_analytic = 0;

  [[nodiscard]] bool triangle_only() const { return spheres + ellipsoids + disks + boxes == 0; }
  [[nodiscard]] bool all_float() const { return non_float_vertices == 0 && non_float_analytic == 0; }
};

/// The analysis of `s` with slivers counted above `sliver_aspect` (> 1).
[[nodiscard]] SceneAnalysis analyse_scene(const Scene& s, double sliver_aspect = 1000);

/// Whether p0, p1, p2 are collinear (a zero-area triangle), exactly; nothing for a non-finite
/// coordinate or coordinates spread over more than 2^400 within the triangle (not decided here).
[[nodiscard]] std::optional<bool> collinear_exact(Vec3<double> p0, Vec3<double> p1, Vec3<double> p2);

/// The closed components as meshes of their own (at most `limit`, in component order; 0: all), for
/// leak rays: one pass over the triangles.
[[nodiscard]] std::vector<mesh::Mesh> closed_component_meshes(const Scene& s, const SceneAnalysis& a,
                                                              std::size_t limit = 0);

}  // namespace rayproof::scene
