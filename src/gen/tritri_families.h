#pragma once
/// Pairs of triangles for the triangle/triangle classes (docs/tritri.md): one family per situation
/// that stresses a test (a shared edge, a vertex exactly on a face, coplanar contact, a vertex
/// lifted off the common plane by k ulps, magnitudes near 2^+-600, ...). The constructed families
/// build their contact on an integer lattice and place it exactly (an axis permutation with sign
/// flips, an integer offset, a power-of-two scale), so the pair's exact class is known by
/// construction (`expected`); the random ones leave it to the exact classifiers.
///
/// Determinism: the same (family, count, seed) gives the same pairs bit for bit (own PRNG, integer
/// constructions, exact scalings; see rng.h). Each family draws from its own stream.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rayproof/triangle_common.h"
#include "rayproof/tritri_class.h"

namespace rayproof::gen {

struct TriPair {
  Triangle<double> a, b;
  std::optional<TriTri> expected;  ///< the exact class, where the construction fixes it
  std::optional<bool> expected_meets;  ///< whether they share a point, where the construction fixes it
};

struct TriTriFamily {
  std::string name;
  std::string stresses;  ///< one line: what it stresses
};

/// Every pair family, in a stable order.
[[nodiscard]] const std::vector<TriTriFamily>& tritri_families();
[[nodiscard]] const TriTriFamily* find_tritri_family(std::string_view name);

/// `count` pairs of the family. The near_coplanar family lifts one vertex by k ulps, k cycling
/// through 1, 4, 16, ..., 4^10 with the pair's index (its stiffness knob).
[[nodiscard]] std::vector<TriPair> generate_tritri(const TriTriFamily& f, std::size_t count, std::uint64_t seed);

/// The same pairs, one at a time (for outputs too large to hold).
void generate_tritri_each(const TriTriFamily& f, std::size_t count, std::uint64_t seed,
                          const std::function<void(const TriPair&)>& sink);

/// One near_coplanar pair with the lift given: a coplanar pair (overlapping, touching or apart)
/// with one vertex of b moved k ulps along an axis off the plane (k = 0: the coplanar pair).
[[nodiscard]] TriPair near_coplanar_pair(std::uint64_t seed, std::size_t index, int k_ulps);

}  // namespace rayproof::gen
