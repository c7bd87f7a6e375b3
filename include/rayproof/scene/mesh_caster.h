#pragma once
/// MeshCaster<Method>: closest, any and all hits of rays against a user's triangle mesh, through a
/// wide BVH (binned SAH; scene::Accel: eight-wide nodes with the AVX2 box test where the CPU has
/// AVX2, else four-wide SSE ones; compressed nodes for large meshes), one ray at a time or in
/// batches over TBB threads.
///
/// Contract:
/// - Input: vertices as float or double triples (pointer, count, stride in bytes) and 32-bit
///   indices (pointer, triangle count, stride in bytes). The arrays are checked when the caster is
///   built; bad input throws MeshInputError with a message: a null pointer with a nonzero count, a
///   stride smaller than one element or larger than 65536 bytes, more than 2^32 - 2 triangles or
///   vertices, an array that would run past the end of the address space, an index out of range,
///   a NaN or infinite coordinate in a vertex that a triangle uses (unused vertices are not read).
///   Zero triangles is a valid, empty mesh.
/// - Copies: double vertices packed 24 bytes apart at an 8-byte aligned address are read in place:
///   that array must outlive the caster and stay unchanged. Float vertices and other strides are
///   converted once into a packed double copy (copies_vertices() tells). Indices are read once,
///   while building: the BVH's leaf records keep them, so the index array may be freed afterwards.
/// - Method, chosen at compile time (the kernels of `rayproof cast --method NAME`):
///   cast::Float      Möller–Trumbore on the float-rounded ray and vertices, textbook slab test.
///                    Fast, not watertight: rays slip through shared edges and vertices. A crossing
///                    that the float kernel places, by its rounding, just outside its triangle's
///                    box may be dropped by the box test (so near edges and vertices brute force
///                    over every triangle can find crossings all() does not, and closest() can
///                    differ from all()'s first).
///   cast::Robust     watertight test (Woop, Benthin, Wald 2013) on the float-rounded inputs in
///                    double arithmetic, conservative traversal (Ize 2013): exactly the crossings
///                    of that test on every triangle; no ray leaks between triangles that share an
///                    edge or vertex.
///   cast::Certified  certified filter in double (rayproof/certified_triangle.h): the exact class,
///                    t within 1 ulp of the exact t of the double inputs, conservative traversal.
///                    Where the filter cannot decide: rayproof::certified::intersect (its exact
///                    fallback: GMP, MPFR; no CGAL). A program using MeshCaster<cast::Certified>
///                    links rayproof_scene_certified, which brings rayproof_certified (else: an
///                    undefined reference to MeshCaster<cast::Certified>'s constructor).
/// - Results (MeshHit): triangle number (its position in the index array), t, contact class
///   (interior / edge / vertex / coplanar, docs/cases.md) and barycentrics b1 (weight of the triangle's
///   second vertex) and b2 (third) as the Float and Robust kernels compute them. Certified's
///   traversal decides class and t only: its b1, b2 are NaN (for barycentrics within 2^-50 of the
///   exact ones, call rayproof::certified::intersect, rayproof/certified/intersect.h, on the hit triangle).
///   A coplanar touch (a segment) has none either. A miss has triangle == kNoTriangle.
/// - Ranges: a crossing counts when tmin <= t <= tmax. closest(): the least t, ties to the lower
///   triangle number. any(): whether a crossing exists. all(): every crossing sorted by t, then
///   triangle. A ray with a NaN or infinite component or a zero direction has no crossing
///   (closest() gives contact `invalid`). Degenerate (zero-area) triangles are never hit.
/// - Threads: a caster is move-only; its queries are const and may run concurrently. The batch
///   calls run on a TBB arena of `threads` threads (0: TBB's default, all hardware threads).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include "rayproof/contact.h"
#include "rayproof/float_util.h"
#include "rayproof/ray.h"

namespace rayproof {

/// The methods a MeshCaster is compiled for (tags).
namespace cast {
struct Float {};
struct Robust {};
struct Certified {};
}  // namespace cast

/// Bad mesh arrays or batch spans: the message says which and why.
class MeshInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A vertex array: `count` points of three floats or doubles, the first at `data`, each
/// `stride` bytes after the previous one (default: packed).
struct VertexArray {
  const void* data = nullptr;
  std::size_t count = 0;
  std::size_t stride = 0;
  bool is_double = true;

  VertexArray(const double* p, std::size_t n, std::size_t stride_bytes = 3 * sizeof(double))
      : data(p), count(n), stride(stride_bytes), is_double(true) {}
  VertexArray(const float* p, std::size_t n, std::size_t stride_bytes = 3 * sizeof(float))
      : data(p), count(n), stride(stride_bytes), is_double(false) {}
};

/// An index array: `triangles` triples of 32-bit vertex numbers, `stride` bytes apart.
struct IndexArray {
  const std::uint32_t* data = nullptr;
  std::size_t triangles = 0;
  std::size_t stride = 3 * sizeof(std::uint32_t);
};

/// One crossing of a ray with the mesh.
struct MeshHit {
  static constexpr std::uint32_t kNoTriangle = 0xffffffffu;
  std::uint32_t triangle = kNoTriangle;
  Contact contact = Contact::miss;
  double t = kNaN<double>;
  double b1 = kNaN<double>, b2 = kNaN<double>;  ///< weights of the triangle's 2nd and 3rd vertex
  [[nodiscard]] bool hit() const { return triangle != kNoTriangle; }
};

/// A ray's range of t: a crossing counts when tmin <= t <= tmax.
struct TRange {
  double tmin = 0;
  double tmax = std::numeric_limits<double>::infinity();
};

namespace scene::detail {
struct MeshState;  // the BVH, the vertices (or a view of the user's) and the method: src/scene
struct MeshStateDeleter {
  void operator()(const MeshState* s) const;
};
using MeshStatePtr = std::unique_ptr<const MeshState, MeshStateDeleter>;
}  // namespace scene::detail

template <class Method>
class MeshCaster {
 public:
  /// Builds the BVH (on the calling TBB arena's threads). Throws MeshInputError on bad input.
  MeshCaster(const VertexArray& vertices, const IndexArray& indices);

  [[nodiscard]] std::size_t triangle_count() const;
  /// Whether the vertices were converted into a copy (float input, or not packed doubles).
  [[nodiscard]] bool copies_vertices() const;
  /// Seconds the BVH build took; bytes held per triangle: BVH nodes, leaf records, packed leaf
  /// groups and the double vertices (the user's, when read in place).
  [[nodiscard]] double build_seconds() const;
  [[nodiscard]] double bytes_per_triangle() const;
  /// Bytes per triangle this method's queries read: Float and Robust the nodes and the packed leaf
  /// groups (not the leaf records or the vertices, unless RAYPROOF_SIMD=off); Certified the nodes,
  /// the leaf records and the double vertices.
  [[nodiscard]] double bytes_read_per_triangle() const;

  [[nodiscard]] MeshHit closest(const Ray<double>& ray, TRange range = {}) const;
  [[nodiscard]] bool any(const Ray<double>& ray, TRange range = {}) const;
  [[nodiscard]] std::vector<MeshHit> all(const Ray<double>& ray, TRange range = {}) const;

  /// closest() of every ray into `out` (same size as `rays`). `ranges`: empty ([0, inf) for
  /// all), one range for all rays, or one per ray; anything else throws MeshInputError.
  void closest(std::span<const Ray<double>> rays, std::span<const TRange> ranges, std::span<MeshHit> out,
               int threads = 0) const;
  /// any() of every ray into `out` (1: a crossing in range, 0: none).
  void any(std::span<const Ray<double>> rays, std::span<const TRange> ranges, std::span<std::uint8_t> out,
           int threads = 0) const;

 private:
  scene::detail::MeshStatePtr state_;
};

extern template class MeshCaster<cast::Float>;
extern template class MeshCaster<cast::Robust>;
extern template class MeshCaster<cast::Certified>;

}  // namespace rayproof
