#pragma once
/// The first pass of the closest-point query on the wide tree (internal; distance_wide.cpp): a
/// nearest-child-first search in plain double over DistanceTree::wide8 (eight box distances per
/// AVX2 test) or wide4 (four per SSE test) for a tight upper bound U of the answer's squared
/// distance, and the triangles it visits with their lower bounds.
#include <cstdint>
#include <vector>

#include "rayproof/vec3.h"
#include "scene/distance_tree.h"

namespace rayproof::scene::detail {

/// A triangle the first pass visited within its bound: its slot, a lower bound of its squared
/// distance to p (rounded down: its box's), and the direction from the point its upper bound found
/// to p (for lower_bound_along).
struct DistanceVisit {
  std::uint32_t slot;
  double lb;
  Vec3<double> dir;
};

/// Lowers U (a rigorous upper bound of the squared distance from p to the mesh, +inf for none yet)
/// to the least upper bound of the triangles it visits, and appends to `visited` every triangle it
/// visits whose box lies within U at that time, with a lower bound: each triangle within the final
/// U of p is among them (U only decreases, and the float box test drops only boxes surely beyond it). False, with nothing done, when p is
/// out of the float test's range (a coordinate beyond 2^100) or the tree has no wide copy: then
/// the caller takes the binary tree.
[[nodiscard]] bool wide_first_bound(const DistanceTree& t, const Vec3<double>& p, double& U, std::vector<DistanceVisit>& visited);

}  // namespace rayproof::scene::detail
