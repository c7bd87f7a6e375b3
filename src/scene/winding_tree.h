#pragma once
/// The generalized winding number over a tree with a far-field expansion and a guaranteed bound
/// (internal to rayproof_scene_certified; the public face is ExactMesh::winding_value and
/// ContainsRule::winding). The derivations are in winding_tree.cpp.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/winding.h"

namespace rayproof::scene::detail {

/// One triangle's solid angle at p with a bound on its error: |Omega_exact - omega| <= err.
/// status: 0 bounded; 1 unresolved in this precision (p on or within rounding of the triangle's
/// plane and closure, or coordinates out of the double window); 2 p is on the closed triangle.
struct SolidAngle {
  double omega = 0, err = 0;
  int status = 0;
};

/// A triangle whose double bound exceeds this (p within about 1e-6 relative of its plane and
/// edges) is evaluated again in MPFR, whose bound is tighter by 2^75 or more.
inline constexpr double kLooseSolidAngle = 0x1p-36;
/// The solid angle of triangle abc at p in double with its rounding bound (status 0 or 1).
[[nodiscard]] SolidAngle solid_angle_double(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                            const Vec3<double>& p);
/// The brute force in MPFR at `bits`; *vs_half: +1 when w > 1/2 is proven, -1 when w < 1/2, 0
/// when undecided at this precision (or p is on the surface).
[[nodiscard]] WindingValue winding_mpfr(std::span<const Vec3<double>> vertices,
                                        std::span<const std::array<std::uint32_t, 3>> triangles, const Vec3<double>& p,
                                        int bits, int* vs_half);
/// The exact decision and, when needed, MPFR at increasing precision (status 0 or 2): used where
/// the double evaluation is unresolved (winding_mpfr.cpp).
[[nodiscard]] SolidAngle solid_angle_resolved(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                              const Vec3<double>& p);
/// p on the closed triangle abc (exact; false for zero area).
[[nodiscard]] bool on_closed_triangle_exact(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c,
                                            const Vec3<double>& p);

/// A running sum of solid angles with its bound (see winding_tree.cpp for the summation bound).
struct WindingSum {
  double sum = 0, err = 0, abs = 0;
  std::uint64_t terms = 0;
  void add(double omega, double e) {
    sum += omega;
    err += e;
    abs += omega < 0 ? -omega : omega;
    ++terms;
  }
  /// w = sum / 4 pi with every error of the sum included.
  [[nodiscard]] WindingValue value() const;
};

/// Switches read when a WindingTree is built (each tree keeps its own copy): the defaults are the
/// fastest measured on most meshes (docs/contains.md); `rayproof bench contains --open` builds
/// meshes with one switch changed to measure its effect in the same run (the ablation). Not
/// thread-safe to change while trees are being built.
struct WindingTuning {
  /// Nodes whose ball excludes p but that are too near for the expansion contribute 0 with the
  /// bound area / (d - r)^2 (section 2b of winding_tree.cpp) instead of being opened.
  bool near_bound = true;
  /// Caps as hierarchical fans over the boundary's closed walks (compact triangles) instead of a
  /// cone from one apex per boundary component (winding_caps.cpp).
  bool compact_caps = true;
  /// Triangles per leaf of the caps' tree (the full tree keeps 6).
  std::size_t caps_leaf = 6;
  /// The caps' winding number tabulated over an octree with a bound per cell (CapsField), read
  /// before the caps' tree is refined per point.
  bool caps_field = true;
};
[[nodiscard]] WindingTuning& winding_tuning();

/// p in the closed box [lo, hi] (false for NaN).
[[nodiscard]] inline bool in_closed_box(const Vec3<double>& lo, const Vec3<double>& hi, const Vec3<double>& p) {
  return lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y && lo.z <= p.z && p.z <= hi.z;
}

/// The octant of p about a cell's midpoint m: bit 0, 1, 2 set when p is above m in x, y, z. The
/// caps' field splits its sample and descends with this one comparison, so that a point is always
/// in the closed box of the child it descends to.
[[nodiscard]] inline int octant_of(const Vec3<double>& p, const Vec3<double>& m) {
  return int(p.x > m.x) | int(p.y > m.y) << 1 | int(p.z > m.z) << 2;
}

class WindingTree;
/// The caps' winding number tabulated over an octree of the capped mesh's box (winding_field.cpp):
/// per leaf cell a value w0 at its centre and a bound e with |w_caps(p) - w0| <= e for every p in
/// the closed cell, or no value (a cap meets the cell). Built once with the caps.
class CapsField {
 public:
  /// Cells up to `max_cells` in all, subdivided while the far part's spread is large or a cell has
  /// many near triangles; with a `sample` of points (the first batch's), only cells that hold some
  /// of them are subdivided or valued below the top two levels.
  CapsField(const WindingTree& caps, const Vec3<double>& lo, const Vec3<double>& hi, std::size_t max_cells,
            std::span<const Vec3<double>> sample = {});
  /// The caps' winding number at p from its cell: the tabulated far part plus the cell's near
  /// triangles evaluated at p, with its bound; false outside the box, in a cell without a value,
  /// or when a near triangle needs more than double (p within rounding of its plane).
  bool value(const Vec3<double>& p, double* w, double* bound) const;
  [[nodiscard]] std::size_t cells() const { return cells_.size(); }
  [[nodiscard]] std::size_t valued_cells() const { return valued_; }

 private:
  struct Cell {
    double w0 = 0, e = 0;     ///< the far part at the centre, and its bound over the cell
    std::int32_t child = -2;  ///< first of 8 children; -1 a leaf with a value; -2 a leaf without
    std::uint32_t near_first = 0, near_count = 0;  ///< in near_
  };
  const WindingTree* caps_;
  Vec3<double> lo_, hi_;
  std::vector<std::uint32_t> near_;  ///< the cells' near triangles (leaf order of caps_)
  std::vector<Cell> cells_;
  std::size_t valued_ = 0;
};

/// A binary tree over the triangles with per-node moments (Barill et al. 2018, first order: area
/// vector and first moment about the node's centre) and a bounding ball.
class WindingTree {
 public:
  /// `leaf_size`: at most this many triangles per leaf (1 to 64).
  WindingTree(const std::vector<Vec3<double>>& v, const std::vector<std::array<std::uint32_t, 3>>& t,
              std::size_t leaf_size = 6);

  /// w(p) with far-field terms for the nodes seen at a radius-to-distance ratio <= beta (beta in
  /// [0, 0.9]; 0: every triangle directly) and an exact near field.
  [[nodiscard]] WindingValue eval(const Vec3<double>& p, double beta) const;
  /// w(p) refined until bound <= tolerance or no refinement is left (then the direct evaluation of
  /// every triangle, its bound a few ulps per triangle).
  [[nodiscard]] WindingValue value(const Vec3<double>& p, double tolerance) const;
  /// inside (w > 1/2), outside (w < 1/2) or surface, refined until decided; `tie` set when even the
  /// MPFR evaluation at the highest precision tried leaves |w - 1/2| within its bound (w = 1/2
  /// exactly, or within about 2^-1000 of it): then the answer is outside.
  [[nodiscard]] Side side(const Vec3<double>& p, bool* tie = nullptr) const;

  [[nodiscard]] std::size_t node_count() const { return nodes_.size(); }
  /// Refinement by largest error first: starting from the root, the node whose far-field bound is
  /// largest is replaced by its children (a leaf by its triangles, evaluated directly) until
  /// `done(w, bound)` holds for the rigorous value or nothing is left to refine (then every triangle
  /// has been evaluated directly). Nodes seen at a ratio r / d above kQMax are opened at once.
  /// Refines the value of this tree's triangles until |offset - w - 1/2| > bound (or nothing is
  /// left to refine): for w = offset - (this tree's w).
  [[nodiscard]] WindingValue value_against(const Vec3<double>& p, double offset) const;
  template <class Done>
  [[nodiscard]] WindingValue refine(const Vec3<double>& p, Done&& done) const;
  /// An upper bound on |grad w_far| over the ball (x0, h), w_far the winding number of this tree's
  /// triangles less the `near` ones (section 4 of winding_tree.cpp): |w_far(p) - w_far(x0)| <=
  /// bound * |p - x0| for p in the ball. A triangle is near when it may meet the ball, or when its
  /// share of bound * h would exceed tau: its leaf-order index is appended to `near` (at most
  /// max_near of them; +inf when there would be more, or without a list).
  [[nodiscard]] double gradient_bound(const Vec3<double>& x0, double h, double tau = 0,
                                      std::vector<std::uint32_t>* near = nullptr, std::size_t max_near = 0) const;
  /// Triangle i in leaf order (the indices gradient_bound lists).
  [[nodiscard]] const std::array<Vec3<double>, 3>& leaf_triangle(std::uint32_t i) const { return tris_[i]; }
  [[nodiscard]] std::size_t triangle_count() const { return tris_.size(); }
  static constexpr double kQMax = 0.5;

 private:
  struct Node {
    double c[3];   ///< centre (area-weighted centroid)
    double r;      ///< radius of a ball about c holding every vertex of the node's triangles
    double area;   ///< sum of the triangles' unsigned areas
    double area_up;  ///< a rigorous upper bound on that sum (rounding and underflow included)
    double n[3];   ///< sum of the area vectors (half cross products)
    double m[9];   ///< first moment m[3 i + j] = sum area_vector_i (centroid - c)_j
    std::uint32_t first, count;  ///< leaf: its triangles in tris_; inner: count = 0, children first, first + 1
  };
  std::vector<Node> nodes_;
  std::vector<std::array<Vec3<double>, 3>> tris_;  ///< leaf order
  std::vector<Vec3<double>> vertices_;             ///< for the MPFR stage
  std::vector<std::array<std::uint32_t, 3>> triangles_;
  std::size_t leaf_size_ = 6;
  bool near_bound_ = true;
  void build(std::vector<std::uint32_t>& ids, std::size_t lo, std::size_t hi, const std::vector<Vec3<double>>& cen,
             std::uint32_t self, int depth);
};

}  // namespace rayproof::scene::detail
