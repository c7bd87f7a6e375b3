#pragma once
/// The parts of ExactMesh::ray_crossings' speed that can be switched off one at a time, for the
/// ablation of `rayproof bench crossings --ablation` (internal to rayproof_scene_certified and its
/// benches). The answers are the same either way (only the work differs; the bench compares them).
namespace rayproof::scene::detail {

struct CrossingsSpeedups {
  /// Traverse the exact range [tmin, tmax] (the float box test when tmin >= 0) rather than one two
  /// ulps wider (tmin < 0 for the default range: the double box test).
  bool float_traversal = true;
  /// Stage 1's proven misses four triangles at a time (AVX2 lanes) before the scalar filter.
  bool lane_misses = true;
  /// A vertex's or an edge's fan decided once per contact: vertices on the ray and edges with edge
  /// function 0 remembered per ray (their signs, the edge contact's t). Off by default: measured
  /// no gain (rays through vertices and edges on bunny00, armadillo and the generated sphere: the
  /// same or up to 6% slower with it; docs/contains.md).
  bool fan_once = false;
};

void set_crossings_speedups(const CrossingsSpeedups& s);
[[nodiscard]] CrossingsSpeedups crossings_speedups();

}  // namespace rayproof::scene::detail
