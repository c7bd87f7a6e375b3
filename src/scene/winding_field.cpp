// The caps' winding number tabulated over an octree of the capped mesh's box. On an open mesh the
// winding rule decides w_mesh(p) = W(p) - w_caps(p) > 1/2 (winding_caps.cpp), and w_caps is a sum
// over every hole: on a mesh with a hundred holes spread over it, refining the caps' tree per
// point opens hundreds of nodes before the bound falls below the margin, while the exact W costs
// what contains on a closed mesh does. So the caps are split per cell of an octree into a few near
// triangles, evaluated at each point, and the far rest, which is smooth on the cell and tabulated
// once: its value at the centre x0 (the caps' tree refined to 1/16, less the near triangles) and a
// bound on how far it moves within the cell (section 4 of winding_tree.cpp: |grad w_far| times the
// cell's half-diagonal h). A point then costs a descent of the octree, its cell's near triangles
// and one comparison; cells without a value, and points whose margin is below their bound, go to
// the caps' tree as before.
#include <algorithm>
#include <cmath>
#include <deque>

#include "scene/winding_tree.h"

namespace rayproof::scene::detail {

namespace {

constexpr double kUp = 1.0 + 0x1p-40;
/// A cell is split while the far part's spread exceeds half this, or it has more than kSplitNear
/// near triangles (and depth and budget allow).
constexpr double kCellBound = 1.0 / 2;
constexpr std::size_t kSplitNear = 8;
/// A cell with more near triangles than this has no value.
constexpr std::size_t kMaxNear = 48;
/// The share of the spread above which a far triangle counts as near.
constexpr double kTau = 1.0 / 128;
/// The caps' tree is refined at the centre to this bound.
constexpr double kCentreTolerance = 1.0 / 16;
constexpr int kMaxDepth = 10;

inline Vec3<double> mid(const Vec3<double>& a, const Vec3<double>& b) {
  return {0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z)};
}

/// The sum of the listed triangles' solid angles at p over 4 pi, with its bound; false when p is
/// on one of them.
bool near_sum(const WindingTree& caps, const std::uint32_t* ids, std::size_t n, const Vec3<double>& p,
              WindingValue* out) {
  WindingSum s;
  for (std::size_t k = 0; k < n; ++k) {
    const auto& T = caps.leaf_triangle(ids[k]);
    SolidAngle a = solid_angle_double(T[0], T[1], T[2], p);
    if (a.status != 0 || a.err > kLooseSolidAngle) a = solid_angle_resolved(T[0], T[1], T[2], p);
    if (a.status == 2) return false;
    s.add(a.omega, a.err);
  }
  *out = s.value();
  return true;
}

}  // namespace

CapsField::CapsField(const WindingTree& caps, const Vec3<double>& lo, const Vec3<double>& hi, std::size_t max_cells,
                     std::span<const Vec3<double>> sample)
    : caps_(&caps), lo_(lo), hi_(hi) {
  struct Pending {
    std::uint32_t cell;
    Vec3<double> a, b;
    int depth;
    std::size_t pb, pe;  ///< the sample points in the cell: pts[pb, pe)
  };
  // The sample's points in the box (the caller strides it), partitioned down the octree.
  std::vector<Vec3<double>> pts, scratch;
  for (const Vec3<double>& p : sample)
    if (in_closed_box(lo, hi, p)) pts.push_back(p);
  const bool sampled = !sample.empty();
  std::deque<Pending> queue;
  std::vector<std::uint32_t> near;
  cells_.emplace_back();
  queue.push_back({0, lo, hi, 0, 0, pts.size()});
  while (!queue.empty()) {
    const Pending c = queue.front();
    queue.pop_front();
    // With a sample, cells below the top two levels that hold none of its points are left without
    // a value: the budget goes where the points are (a later point there goes to the caps' tree).
    if (sampled && c.depth >= 2 && c.pb == c.pe) continue;
    const Vec3<double> x0 = mid(c.a, c.b);
    if (!(std::isfinite(x0.x) && std::isfinite(x0.y) && std::isfinite(x0.z))) continue;  // no value
    // h >= the distance from x0 to every point of the closed cell (each offset within an ulp).
    const double hx = std::max(x0.x - c.a.x, c.b.x - x0.x), hy = std::max(x0.y - c.a.y, c.b.y - x0.y),
                 hz = std::max(x0.z - c.a.z, c.b.z - x0.z);
    const double h = std::sqrt(hx * hx + hy * hy + hz * hz) * (kUp * kUp);
    near.clear();
    const double grad = caps.gradient_bound(x0, h, kTau, &near, kMaxNear);
    const double spread = grad * h * kUp;  // inf: too many near triangles
    const bool can_split = c.depth < kMaxDepth && cells_.size() + 8 <= max_cells;
    if ((!(spread <= kCellBound / 2) || near.size() > kSplitNear) && can_split) {
      const auto first = std::int32_t(cells_.size());
      cells_[c.cell].child = first;
      cells_.resize(cells_.size() + 8);
      // The cell's points by octant, as value() descends.
      std::size_t start[9] = {};
      for (std::size_t i = c.pb; i < c.pe; ++i) ++start[octant_of(pts[i], x0) + 1];
      for (int o = 0; o < 8; ++o) start[o + 1] += start[o];
      scratch.resize(c.pe - c.pb);
      std::size_t fill[8];
      for (int o = 0; o < 8; ++o) fill[o] = start[o];
      for (std::size_t i = c.pb; i < c.pe; ++i) scratch[fill[octant_of(pts[i], x0)]++] = pts[i];
      std::copy(scratch.begin(), scratch.end(), pts.begin() + std::ptrdiff_t(c.pb));
      for (int o = 0; o < 8; ++o) {
        Pending k{std::uint32_t(first + o), c.a, c.b, c.depth + 1, c.pb + start[o], c.pb + start[o + 1]};
        (o & 1 ? k.a.x : k.b.x) = x0.x;
        (o & 2 ? k.a.y : k.b.y) = x0.y;
        (o & 4 ? k.a.z : k.b.z) = x0.z;
        queue.push_back(k);
      }
      continue;
    }
    if (!(spread < 0.5)) continue;  // the bound would decide nothing
    // The far part at x0: every cap less the near ones (x0 on a cap: no value).
    const WindingValue all = caps.value(x0, kCentreTolerance);
    WindingValue part;
    if (all.surface || !std::isfinite(all.w) || !near_sum(caps, near.data(), near.size(), x0, &part)) continue;
    const double w0 = all.w - part.w;
    const double e = (all.bound + part.bound + spread + 0x1p-50 * (std::fabs(all.w) + std::fabs(part.w))) * kUp;
    if (!(e < 0.5)) continue;
    cells_[c.cell] = {w0, e, -1, std::uint32_t(near_.size()), std::uint32_t(near.size())};
    near_.insert(near_.end(), near.begin(), near.end());
    ++valued_;
  }
}

bool CapsField::value(const Vec3<double>& p, double* w, double* bound) const {
  if (!in_closed_box(lo_, hi_, p)) return false;
  Vec3<double> a = lo_, b = hi_;
  std::uint32_t i = 0;
  while (cells_[i].child >= 0) {
    // The same midpoints as the build: p is in the closed box of the child it descends to.
    const Vec3<double> m = mid(a, b);
    const int o = octant_of(p, m);
    (o & 1 ? a.x : b.x) = m.x;
    (o & 2 ? a.y : b.y) = m.y;
    (o & 4 ? a.z : b.z) = m.z;
    i = std::uint32_t(cells_[i].child + o);
  }
  const Cell& c = cells_[i];
  if (c.child != -1) return false;
  WindingValue part;
  if (!near_sum(*caps_, near_.data() + c.near_first, c.near_count, p, &part)) return false;
  *w = c.w0 + part.w;
  *bound = (c.e + part.bound + 0x1p-50 * (std::fabs(c.w0) + std::fabs(part.w))) * kUp;
  return true;
}

}  // namespace rayproof::scene::detail
