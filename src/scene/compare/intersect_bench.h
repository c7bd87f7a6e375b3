#pragma once
/// The measuring half of `rayproof bench intersect` (docs/intersect.md): rayproof's exact
/// self-intersections and contact pairs on one thread beside CGAL PMP's self_intersections (Epick;
/// Epeck on small meshes), Open3D's TriangleMesh.get_self_intersecting_triangles (a Python child
/// process) and FCL's mesh-mesh collision (two meshes); for each peer its pairs, the pairs that
/// differ from rayproof's exact set and the time ratio, all from one run. The generated meshes with
/// known contacts and the sentences printed about each peer are here too, so that a test can build
/// the sentences from known tallies. The tool parses the options and prints what these return.
#include <cstddef>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/intersections.h"
#include "scene/compare/intersect_compare.h"

namespace rayproof::scene::compare {

/// What one peer found beside rayproof on one row. `reference` is rayproof's pairs in the peer's
/// scope: all of them, or for Open3D those sharing no vertex index (and not a zero-area triangle's
/// (i, i)), the only ones it looks for; `missing` are reference pairs the peer did not report,
/// `extra` the peer's pairs not in the reference. Times: least thread CPU time (Open3D: process CPU
/// time of the call in the child) of the timed runs.
struct PeerRow {
  std::string peer;  ///< "CGAL PMP Epick", "CGAL PMP Epeck", "Open3D", "FCL"
  bool restricted = false;  ///< compared with rayproof's pairs that share no vertex index (Open3D)
  bool ran = false;
  std::string note;  ///< why it did not run
  std::size_t pairs = 0, reference = 0, missing = 0, extra = 0;
  double seconds = 0;
};

/// One mesh (self-intersections) or two (contact pairs) and every peer beside rayproof.
struct IntersectRow {
  std::string name;
  std::size_t triangles = 0, triangles2 = 0;  ///< triangles2: the second mesh's (two meshes only)
  bool two = false;
  std::size_t pairs = 0;  ///< rayproof's
  double seconds = 0;     ///< rayproof's least thread CPU time, one thread
  std::vector<PeerRow> peers;
};

struct IntersectBenchOptions {
  int repeat = 3;                       ///< timed runs per method (least time kept)
  std::size_t epeck_max = 5000;         ///< CGAL with Epeck only up to this many triangles
  std::size_t open3d_max = 20000;       ///< Open3D (every pair: O(n^2)) only up to this many
  std::string python = "/usr/bin/python3";  ///< the interpreter with open3d (Debian's python3-open3d)
  bool peers = true;                    ///< false: rayproof alone
};

/// The generated meshes of the default set, each with contacts known by construction: two bumpy
/// spheres of 20,480 triangles overlapping (one mesh), a bumpy sphere of 5,120 triangles and its copy
/// moved by one ulp in x (one mesh: every triangle meets its copy and the copy's neighbours), and a
/// 60 x 60 sheet folded onto itself along x = 25 (7,200 triangles).
struct NamedMesh {
  std::string name;
  mesh::Mesh mesh;
};
[[nodiscard]] std::vector<NamedMesh> generated_intersect_meshes();

/// `a` with `b` appended (b's indices shifted: no index shared), as one mesh.
[[nodiscard]] mesh::Mesh joined(const mesh::Mesh& a, const mesh::Mesh& b);
/// `m` with every vertex moved by d.
[[nodiscard]] mesh::Mesh moved(mesh::Mesh m, Vec3<double> d);
/// `m` with every x coordinate moved up by one ulp.
[[nodiscard]] mesh::Mesh moved_one_ulp(mesh::Mesh m);
/// `m` moved by (0.3, 0.1, 0.05) times its bounding box's sides (the contact pairs' copy).
[[nodiscard]] mesh::Mesh shifted_copy(const mesh::Mesh& m);

/// Pairs of `a` not in `b` (both sorted).
[[nodiscard]] std::size_t pairs_missing_from(const std::vector<TrianglePair>& a, const std::vector<TrianglePair>& b);
/// The pairs (i, j), i != j, of triangles that share no vertex index.
[[nodiscard]] std::vector<TrianglePair> pairs_sharing_no_index(const mesh::Mesh& m,
                                                               const std::vector<TrianglePair>& pairs);

/// Open3D's get_self_intersecting_triangles in a child process of `python`: the mesh is passed as
/// raw arrays in temporary files, the child times the call alone (process CPU time, least of
/// `repeat`) and writes the pairs back. Does not run (note) when the interpreter or open3d is
/// missing, or the child fails or takes over 10 minutes.
[[nodiscard]] PeerPairs open3d_self_intersections(const std::string& python, const mesh::Mesh& m, int repeat);

/// The self-intersections row of `m`: rayproof, then CGAL Epick, CGAL Epeck (up to epeck_max
/// triangles) and Open3D (up to open3d_max). Throws MeshInputError on bad coordinates or indices.
[[nodiscard]] IntersectRow self_intersect_row(const std::string& name, const mesh::Mesh& m,
                                              const IntersectBenchOptions& opt);
/// The contact pairs row of a and b: rayproof's intersecting_pairs, then FCL.
[[nodiscard]] IntersectRow contact_row(const std::string& name, const mesh::Mesh& a, const mesh::Mesh& b,
                                       const IntersectBenchOptions& opt);

/// peer / rayproof time as printed ("2.02x"), or "n/a" when rayproof's time is not positive.
[[nodiscard]] std::string time_ratio_text(double peer_seconds, double ours_seconds);
/// The sentence about one peer on one row, e.g. "CGAL PMP Epick: 173 pairs, the same as
/// rayproof's 173; its time 3.39x rayproof's (rayproof faster)." Every number in it is one printed
/// in the table beside it.
[[nodiscard]] std::string peer_sentence(const IntersectRow& row, const PeerRow& p);

}  // namespace rayproof::scene::compare
