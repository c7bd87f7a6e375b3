// The stand-in for intersect_compare.cpp in builds without RAYPROOF_BUILD_BENCH: CGAL PMP's
// self_intersections header alone costs about 45 s of compile, so the tool's ordinary build leaves
// the linked peers of `bench intersect` out and says so.
#include "scene/compare/intersect_compare.h"

namespace rayproof::scene::compare {

namespace {

PeerPairs not_built() {
  PeerPairs p;
  p.note = "not built in this build (configure with -DRAYPROOF_BUILD_BENCH=ON)";
  return p;
}

}  // namespace

PeerPairs cgal_self_intersections(const mesh::Mesh&, bool, int) { return not_built(); }
PeerPairs fcl_contact_pairs(const mesh::Mesh&, const mesh::Mesh&, int) { return not_built(); }
bool intersect_peers_built() { return false; }

}  // namespace rayproof::scene::compare
