#pragma once
/// Self-intersections of a triangle mesh and contact pairs between two meshes, exact (docs/intersect.md).
/// Candidate pairs come from a BVH over the triangles' boxes (float bounds rounded outwards, so no
/// contact is lost); each candidate is decided by the certified triangle/triangle tests
/// (rayproof/certified/tritri.h): the answer is exact for every double input.
///
/// self_intersections: the pairs of CGAL Polygon_mesh_processing::self_intersections. Adjacency
/// is by vertex index, as given (equal coordinates under different indices are not shared):
///  - no shared index: the closed triangles share a point;
///  - one shared index: they share a point other than that vertex;
///  - two or three shared indices (an edge): they are coplanar and overlap with positive area (the
///    third vertices strictly on the same side of the shared edge);
///  - a zero-area triangle i (collinear or coincident vertices) is reported once, as the pair (i, i),
///    and in no other pair (as CGAL does); certified::tritri_meets answers its contacts.
/// intersecting_pairs: the pairs (i in a, j in b) whose closed triangles share a point (no
/// adjacency between two meshes; zero-area triangles as the segments or points they are).
///
/// Input: the arrays of MeshCaster (rayproof/scene/mesh_caster.h); an index outside the vertices
/// or a NaN or infinite coordinate of a used vertex throws MeshInputError. Output: sorted by (i, j),
/// the same for every number of threads (TBB arena of `threads` threads; 0: TBB's default).
/// Link rayproof::scene_certified.
#include <compare>
#include <cstdint>
#include <vector>

#include "rayproof/scene/mesh_caster.h"
#include "rayproof/tritri_class.h"

namespace rayproof {

/// A triangle mesh as arrays (not copied; they must outlive the call).
struct MeshArrays {
  VertexArray vertices;
  IndexArray indices;
};

/// Two triangles that intersect: i < j (i == j: a zero-area triangle of self_intersections), or
/// i of the first mesh and j of the second.
struct TrianglePair {
  std::uint32_t i = 0, j = 0;
  /// The exact class of the two triangles (rayproof/tritri_class.h) when asked for
  /// (IntersectOptions::classes), else TriTri::invalid. A zero-area triangle's pairs: degenerate.
  TriTri cls = TriTri::invalid;
  friend bool operator==(const TrianglePair& a, const TrianglePair& b) { return a.i == b.i && a.j == b.j; }
  friend auto operator<=>(const TrianglePair& a, const TrianglePair& b) {
    return a.i != b.i ? a.i <=> b.i : a.j <=> b.j;
  }
};

struct IntersectOptions {
  int threads = 0;       ///< 0: TBB's default (every core the process may use); 1: this thread only
  bool classes = false;  ///< fill TrianglePair::cls (one more certified::tritri per reported pair)
};

/// The intersecting pairs of one mesh, CGAL PMP's definition (above), sorted.
[[nodiscard]] std::vector<TrianglePair> self_intersections(const VertexArray& vertices, const IndexArray& indices,
                                                           const IntersectOptions& opt = {});
/// The pairs (i in a, j in b) of closed triangles that share a point, sorted.
[[nodiscard]] std::vector<TrianglePair> intersecting_pairs(const MeshArrays& a, const MeshArrays& b,
                                                           const IntersectOptions& opt = {});

}  // namespace rayproof
