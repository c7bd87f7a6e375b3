#pragma once
/// Generalized winding numbers with a guaranteed error bound, on any triangle mesh (open, with
/// holes, cracked, a soup, self-intersecting): w(p) = (sum over the triangles of the signed solid
/// angle they subtend at p) / 4 pi (Jacobson, Kavan and Sorkine-Hornung 2013). On a closed oriented
/// mesh w is the integer winding number; elsewhere it is a real number, near 1 deep inside a mesh
/// with small holes and near 0 far outside. The derivations of the bounds: docs/contains.md and the
/// comments of src/scene/winding_tree.cpp.
///
/// rayproof::ExactMesh (rayproof/scene/exact_mesh.h) answers `contains` on meshes that are not closed
/// with ContainsRule::winding (inside where w > 1/2) and gives w with its bound (winding_value).
/// The functions here are the brute-force references (every triangle, no tree) used by the tests
/// and `rayproof bench contains`.
#include <array>
#include <cstdint>
#include <limits>
#include <span>

#include "rayproof/float_util.h"
#include "rayproof/vec3.h"

namespace rayproof {

/// A generalized winding number and its bound: the exact w(p) of the double inputs lies in
/// [w - bound, w + bound]. `surface`: p lies on a triangle (closed triangle, exact test; zero-area
/// triangles excluded), where w is undefined: then w is NaN and bound 0. For an invalid point (NaN
/// or infinite coordinate) w is NaN and bound infinite.
struct WindingValue {
  double w = kNaN<double>;
  double bound = std::numeric_limits<double>::infinity();
  bool surface = false;
};

/// Every triangle's solid angle in double with its rounding bound; a triangle whose double
/// evaluation cannot be bounded (p on or within rounding of its plane and closure) is decided
/// exactly (surface, or a zero contribution) or evaluated in MPFR until bounded. Cost: linear in the
/// triangle count. Indices must be in range (std::out_of_range otherwise).
[[nodiscard]] WindingValue winding_brute_force(std::span<const Vec3<double>> vertices,
                                               std::span<const std::array<std::uint32_t, 3>> triangles,
                                               const Vec3<double>& p);

/// The same with every solid angle and the sum in MPFR at `bits` of precision (64 to 65536): a
/// bound near n 2^-bits. The reference of the tests.
[[nodiscard]] WindingValue winding_brute_force_mpfr(std::span<const Vec3<double>> vertices,
                                                    std::span<const std::array<std::uint32_t, 3>> triangles,
                                                    const Vec3<double>& p, int bits);

/// The plain brute-force generalized winding number in double (no bound, no exact test): the
/// baseline `rayproof bench contains` measures against.
[[nodiscard]] double winding_plain_double(std::span<const Vec3<double>> vertices,
                                          std::span<const std::array<std::uint32_t, 3>> triangles,
                                          const Vec3<double>& p);

}  // namespace rayproof
