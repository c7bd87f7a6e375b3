#pragma once
/// fuzz --winding: generalized winding numbers and the winding rule of `contains` on random small
/// meshes, open and closed, against the brute force in MPFR (winding_brute_force_mpfr, every
/// triangle, a bound near n 2^-bits).
/// Meshes: the closed meshes of `fuzz --mesh` (perturbed icospheres, convex hulls; verify/mesh_fuzz.h)
/// kept closed, with random triangles removed (holes), cut along a plane with the vertices of one
/// side duplicated and moved a little (cracks: edges that do not match), with random triangles
/// flipped, with a second copy shifted over the first (self-overlapping), and soups of random
/// triangles; all scaled by a power of two up to 2^+-300.
/// Points (28 a mesh): random in the bounding box, vertices, edge midpoints, points on faces, one-ulp
/// neighbours of vertices and of edge midpoints (holes' rims, cracks), far points.
/// Each point checks, on an ExactMesh built with ContainsRule::winding:
///  (a) winding_value(p)'s interval [w - bound, w + bound] meets the reference's;
///  (b) contains(p) is the reference's side (inside where w > 1/2) wherever the reference keeps
///      |w - 1/2| >= 1e-6 (points nearer are counted and skipped);
///  (c) surface exactly where the reference's exact test says p lies on a triangle (both answers).
/// Every fourth mesh that is not closed also gets a batch: 4096 more points of the same kinds in one
/// batch call of contains, which (with caps of 16 triangles or more) tabulates the caps' field over
/// them and answers through it; the first 512 are asked alone before it: (d) the batch's side
/// equals the side the same point got alone, before the field existed.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "rayproof/scene/exact_mesh.h"

namespace rayproof::verify {

/// The kinds of random mesh, in the order of WindingFuzzResult::kind_meshes.
/// The batch of (d), and how many of its points are also asked alone and compared.
inline constexpr std::size_t kWindingBatch = 4096, kWindingBatchCompared = 512;

enum class WindingMeshKind { closed, holes, crack, flipped, overlap, soup };
inline constexpr std::size_t kWindingMeshKinds = 6;
[[nodiscard]] const char* to_string(WindingMeshKind k);

/// What one point's answers get wrong, judged against the reference.
struct WindingPointVerdict {
  bool near_half = false;     ///< |w - 1/2| < 1e-6 (or too close to tell): the side is not judged
  bool bound_miss = false;    ///< (a): the value's interval misses the reference's
  bool wrong_side = false;    ///< (b)
  bool wrong_surface = false; ///< (c): surface in one answer and not in the reference, or the reverse
  std::string what;           ///< the first thing wrong, in words (empty when nothing)
};

/// Judges a point's answers (value from winding_value, side from contains) against the reference
/// (winding_brute_force_mpfr at the same point).
[[nodiscard]] WindingPointVerdict judge_winding_point(const WindingValue& reference, const WindingValue& value,
                                                      Side side);

struct WindingFuzzOptions {
  double seconds = 0;          ///< stop after this long (0: use max_meshes)
  std::size_t max_meshes = 0;  ///< stop after this many meshes (0: use seconds)
  std::uint64_t seed = 1;
  int bits = 128;              ///< the reference's MPFR precision
  /// The answers under test (tests replace them with wrong ones to see the checker fail): empty
  /// means ExactMesh::winding_value and ExactMesh::contains.
  std::function<WindingValue(const ExactMesh&, const Vec3<double>&)> value;
  std::function<Side(const ExactMesh&, const Vec3<double>&)> contains;
  /// The batch under test, for (d): empty means ExactMesh::contains on the span, one thread.
  std::function<void(const ExactMesh&, std::span<const Vec3<double>>, std::span<Side>)> batch;
};

struct WindingFuzzFinding {
  std::string what;
  std::string off;  ///< the mesh as an OFF file
  Vec3<double> p;
};

struct WindingFuzzResult {
  std::size_t meshes = 0, triangles = 0;
  std::size_t kind_meshes[kWindingMeshKinds] = {};
  std::uint64_t points = 0, surface_points = 0, near_half = 0;
  std::uint64_t bound_misses = 0, wrong_sides = 0, wrong_surfaces = 0;
  std::uint64_t batch_meshes = 0, batch_points = 0;  ///< batch_points: compared with the points alone
  std::uint64_t batch_differ = 0;  ///< (d): the batch's side is not the side the point got alone
  std::uint64_t errors = 0;  ///< a constructor or a query threw on a valid mesh and point
  double seconds = 0;
  std::vector<WindingFuzzFinding> findings;  ///< the first few
  [[nodiscard]] std::uint64_t failures() const { return bound_misses + wrong_sides + wrong_surfaces + batch_differ + errors; }
};

[[nodiscard]] WindingFuzzResult run_winding_fuzz(const WindingFuzzOptions& opt);

}  // namespace rayproof::verify
