#pragma once
/// The peers of `rayproof bench intersect` that are linked libraries: CGAL PMP's
/// self_intersections (Epick, and Epeck) and FCL's mesh-mesh collision. Their headers cost most of
/// a minute of compile, so intersect_compare.cpp is compiled only in builds with
/// RAYPROOF_BUILD_BENCH=ON; other builds get intersect_compare_stub.cpp, whose peers do not run and
/// say why (PeerPairs::note).
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/intersections.h"

namespace rayproof::scene::compare {

/// One peer's answer on one mesh (or pair of meshes): its pairs as rayproof's TrianglePair, sorted
/// and without repeats, and the least thread CPU time of its timed runs. When it did not run, `ran`
/// is false and `note` says why ("not built in this build (...)", "not installed", ...).
struct PeerPairs {
  bool ran = false;
  std::string note;
  std::vector<TrianglePair> pairs;
  double seconds = 0;
};

/// CGAL Polygon_mesh_processing::self_intersections<Sequential_tag> on a Surface_mesh built from the
/// mesh beforehand (not timed), with Epick (exact predicates, inexact constructions) or, when
/// `epeck`, Epeck (exact constructions too); least time of `repeat` runs. Does not run (note) when
/// Surface_mesh refuses a face (not a manifold, oriented mesh).
[[nodiscard]] PeerPairs cgal_self_intersections(const mesh::Mesh& m, bool epeck, int repeat);

/// FCL's collide between BVHModel<OBBRSS> models of a and b (identity transforms), every contact
/// asked for, no contact points; the pairs (triangle of a, triangle of b). The time includes
/// building both models from the arrays, as rayproof's includes its trees; least of `repeat` runs.
[[nodiscard]] PeerPairs fcl_contact_pairs(const mesh::Mesh& a, const mesh::Mesh& b, int repeat);

/// Whether this build has the peers above (intersect_compare.cpp rather than the stand-in).
[[nodiscard]] bool intersect_peers_built();

}  // namespace rayproof::scene::compare
