// ExactMesh's closest-point queries (rayproof/scene/distance.h, docs/distance.md).
//
// A best-first search over the distance tree in double ball arithmetic: every feature of a visited
// triangle (its face, edges and vertices) gets the squared distance from p to the feature's affine
// hull as an interval that surely holds the exact value, and whether p's projection surely falls
// on the feature (then the value is a squared distance to a point of the triangle: an upper bound
// of the answer), surely not (the feature is dropped: another one is nearer), or maybe. The
// answer's squared distance D* is the least value over the features that apply, so it is at most
// U, the least upper end of the sure ones; the features whose lower end is <= U are the only ones
// that can attain D*. When these are all the same geometric feature (one vertex, one edge or one
// face: the same bits in every triangle that shares it) its triangles are exactly tied and the
// lowest index wins; otherwise the exact stage compares their triangles in rationals. The
// distance is the square root of the winner's interval, kept when the rounding is decided for
// every value in it, else recomputed in double-double, else in rationals.
#include <algorithm>
#include <atomic>
#include <limits>
#include <vector>

#include "rayproof/scene/distance.h"
#include "scene/exact_mesh_state.h"
#include "scene/distance_bounds.h"
#include "scene/distance_filter.h"
#include "scene/distance_tree.h"
#include "scene/distance_wide.h"

namespace rayproof {

const char* to_string(DistanceStage s) {
  switch (s) {
    case DistanceStage::filter: return "filter";
    case DistanceStage::rounding: return "rounding";
    case DistanceStage::selection: return "selection";
    case DistanceStage::extreme: return "extreme";
    case DistanceStage::none: return "none";
  }
  return "?";
}

namespace scene::detail {
namespace {


/// A triangle still in the running for the nearest: [lo, hi] encloses its squared distance to the
/// point, at its leaf-order slot, on the feature (kind, k) the filter found nearest; `sure` when that
/// bound is certain enough to lower the search's upper bound.
struct NearCandidate {
  double lo, hi;
  std::uint32_t slot;
  Kind kind;
  std::uint8_t k;
  bool sure;
};

/// Lower bound of the squared distance from p to a box (rounded down).
inline double box_lb(const DistanceNode& n, const Vec3<double>& p) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max({double(n.lo[k]) - p[k], p[k] - double(n.hi[k]), 0.0});
    s += g * g;
  }
  return std::max(0.0, s * (1 - 0x1p-49) - 0x1p-1070);
}

/// Best-first over the binary tree from the root: the nearer child first, boxes whose lower bound
/// is above U skipped (U is read again after each leaf, which may lower it). leaf(first, count) gets
/// a leaf's slots and returns false to stop. False when a degenerate tree is deeper than the stack
/// (128 entries): the search was cut short.
template <class Leaf>
bool binary_best_first(const DistanceTree& t, const Vec3<double>& p, const double& U, Leaf&& leaf) {
  struct Entry {
    std::uint32_t node;
    double lb;
  };
  Entry stack[128];
  int top = 0;
  stack[top++] = {0, box_lb(t.nodes[0], p)};
  while (top) {
    const Entry e = stack[--top];
    if (e.lb > U) continue;
    const DistanceNode& n = t.nodes[e.node];
    if (n.count) {
      if (!leaf(n.index, n.count)) return true;
      continue;
    }
    if (top + 2 > 128) return false;
    const double l0 = box_lb(t.nodes[n.index], p), l1 = box_lb(t.nodes[n.index + 1], p);
    if (l0 <= l1) {
      if (l1 <= U) stack[top++] = {n.index + 1, l1};
      if (l0 <= U) stack[top++] = {n.index, l0};
    } else {
      if (l0 <= U) stack[top++] = {n.index, l0};
      if (l1 <= U) stack[top++] = {n.index + 1, l1};
    }
  }
  return true;
}

struct Search {
  const DistanceTree& t;
  const Vec3<double>& p;
  std::vector<NearCandidate>& c;
  double U = kInf;
  bool extreme = false;

  void push(double lo, double hi, std::uint32_t slot, Kind kind, int k, bool sure) {
    if (!(lo <= hi) || std::isnan(lo)) {  // NaN: over- or underflow in the filter
      extreme = true;
      return;
    }
    if (sure) {
      if (!(hi < kInf)) extreme = true;
      U = std::min(U, hi);
    }
    if (lo <= U) c.push_back({lo, hi, slot, kind, std::uint8_t(k), sure});
  }

  void triangle(std::uint32_t slot) {
    const auto& tri = t.tris[slot];
    if (triangle_box_lb(tri, p) > U) return;  // the triangle's box first: most end here
    double lo, hi;
    // The face's plane: its distance is a lower bound of the triangle's (most visited triangles end
    // here once U is tight); then the face when p projects inside it.
    const bool flat = t.degenerate[slot] != 0;
    BV<BD> ab, ac, ap, n;
    BD h;
    if (!flat) {
      ab = difv<BD>(tri[1], tri[0]), ac = difv<BD>(tri[2], tri[0]), ap = difv<BD>(p, tri[0]);
      n = cross(ab, ac);
      h = dot(n, ap);
      interval(div(mul(h, h), dot(n, n)), lo, hi);
      if (lo > U) return;
    }
    const double plo = lo, phi = hi;
    if (!flat) {  // the face first: when p surely projects inside it, the other features are farther
      const BV<BD> bc = difv<BD>(tri[2], tri[1]), bp = difv<BD>(p, tri[1]), ca = difv<BD>(tri[0], tri[2]),
                   cp = difv<BD>(p, tri[2]);
      const BD s2 = dot(n, cross(ab, ap)), s0 = dot(n, cross(bc, bp)), s1 = dot(n, cross(ca, cp));
      const bool no = negative(s0) || negative(s1) || negative(s2);
      if (!no) {
        const bool sure = positive(s0) && positive(s1) && positive(s2);
        push(plo, phi, slot, kFace, 0, sure);
        if (sure) return;
      }
    }
    // Vertices: always on the triangle.
    for (int k = 0; k < 3; ++k) {
      const BV<BD> w = difv<BD>(p, tri[k]);
      interval(dot(w, w), lo, hi);
      push(lo, hi, slot, kVertex, k, true);
    }
    // Edges: the projection on the line within the segment when both end functions are positive.
    for (int k = 0; k < 3; ++k) {
      Vec3<double> u, v;
      bool sw;
      canonical_edge(tri, k, u, v, sw);
      const BV<BD> d = difv<BD>(v, u), w = difv<BD>(p, u);
      const BD t1 = dot(d, w), t2 = dot(d, difv<BD>(v, p));
      if (negative(t1) || negative(t2)) continue;  // the nearer endpoint is the edge's closest point
      const BV<BD> cr = cross(d, w);
      interval(div(dot(cr, cr), dot(d, d)), lo, hi);
      push(lo, hi, slot, kEdge, k, positive(t1) && positive(t2));
    }
  }

  void run() {
    const bool whole = binary_best_first(t, p, U, [&](std::uint32_t first, std::uint32_t count) {
      for (std::uint32_t s = first; s < first + count; ++s) triangle(s);
      return !extreme;
    });
    if (!whole) extreme = true;  // a degenerate tree deeper than the stack: finish exactly
  }
};

/// The first pass on the binary tree (points beyond the wide tree's float range): best-first in
/// plain double, as wide_first_bound (distance_wide.h) does on the wide tree.
void first_bound(const DistanceTree& t, const Vec3<double>& p, double& U, std::vector<DistanceVisit>& visited, bool& complete) {
  const bool whole = binary_best_first(t, p, U, [&](std::uint32_t first, std::uint32_t count) {
    for (std::uint32_t s = first; s < first + count; ++s) {
      if (triangle_box_lb(t.tris[s], p) > U) continue;
      Vec3<double> dir;
      U = std::min(U, upper_bound(t.tris[s], p, &dir));
      visited.push_back({s, triangle_box_lb(t.tris[s], p), dir});
    }
    return true;
  });
  if (!whole) complete = false;
}

/// The first pass: U from the hint's triangle (a slot, or kNoSlot), then the wide tree (the binary
/// one for points beyond its range).
constexpr std::uint32_t kNoSlot = 0xffffffffu;
double first_pass(const DistanceTree& t, const Vec3<double>& p, std::uint32_t hint, std::vector<DistanceVisit>& visited,
                  bool& complete) {
  double U = kInf;
  if (hint < t.tris.size() && !(distance_ablation() & kAblateHint)) U = upper_bound(t.tris[hint], p);
  if (!(U < kInf)) U = kInf;  // NaN from overflow
  if (!(distance_ablation() & kAblateWide) && wide_first_bound(t, p, U, visited)) return U;
  visited.clear();
  first_bound(t, p, U, visited, complete);
  return U;
}

bool same_feature(const DistanceTree& t, const NearCandidate& a, const NearCandidate& b) {
  if (a.kind != b.kind) return false;
  if (a.kind == kFace) return a.slot == b.slot;
  if (a.kind == kVertex) return t.tris[a.slot][a.k] == t.tris[b.slot][b.k];
  Vec3<double> u0, v0, u1, v1;
  bool s;
  canonical_edge(t.tris[a.slot], a.k, u0, v0, s);
  canonical_edge(t.tris[b.slot], b.k, u1, v1, s);
  return u0 == u1 && v0 == v1;
}

/// The closest point and barycentrics of the winning feature, in double.
void fill_point(const DistanceTree& t, const Vec3<double>& p, const NearCandidate& w, ClosestPoint& r) {
  const auto& tri = t.tris[w.slot];
  std::array<double, 3> b{0, 0, 0};
  if (w.kind == kVertex) {
    b[w.k] = 1;
  } else if (w.kind == kEdge) {
    Vec3<double> u, v;
    bool sw;
    canonical_edge(tri, w.k, u, v, sw);
    const Vec3<double> d = v - u;
    const double s = std::clamp(dot(d, p - u) / dot(d, d), 0.0, 1.0);
    b[w.k] = sw ? s : 1 - s;
    b[(w.k + 1) % 3] = sw ? 1 - s : s;
  } else {
    const Vec3<double> n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    double s[3];
    for (int k = 0; k < 3; ++k) s[k] = std::max(0.0, dot(n, cross(tri[(k + 2) % 3] - tri[(k + 1) % 3], p - tri[(k + 1) % 3])));
    // s[k] is the weight of vertex k: the signed area opposite it.
    const double sum = s[0] + s[1] + s[2];
    for (int k = 0; k < 3; ++k) b[k] = sum > 0 ? s[k] / sum : 1.0 / 3;
  }
  r.barycentric = b;
  r.point = {b[0] * tri[0].x + b[1] * tri[1].x + b[2] * tri[2].x, b[0] * tri[0].y + b[1] * tri[1].y + b[2] * tri[2].y,
             b[0] * tri[0].z + b[1] * tri[1].z + b[2] * tri[2].z};
  if (w.kind == kVertex) r.point = tri[w.k];
  if (w.kind == kFace) {  // the projection on the plane: accurate where the weights are not (slivers)
    const Vec3<double> n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const double nn = dot(n, n);
    if (nn > 0 && std::isfinite(nn)) r.point = p - n * (dot(n, p - tri[0]) / nn);
  }
}

/// The query on the tree's scaled copy, when p and the answer scale exactly (false otherwise).
ClosestPoint query(const DistanceTree& t, const Vec3<double>& p, std::uint32_t hint = kNoSlot);
bool query_scaled(const DistanceTree& t, const Vec3<double>& p, ClosestPoint& r) {
  if (!t.scaled) return false;
  const int e = t.scale_exp;
  const Vec3<double> q{std::ldexp(p.x, -e), std::ldexp(p.y, -e), std::ldexp(p.z, -e)};
  auto exact_down = [&](double c, double d) {
    return std::ldexp(d, e) == c && (d == 0 || std::abs(d) >= std::numeric_limits<double>::min());
  };
  if (!(exact_down(p.x, q.x) && exact_down(p.y, q.y) && exact_down(p.z, q.z))) return false;
  ClosestPoint rs = query(*t.scaled, q);
  const double d = std::ldexp(rs.distance, e);
  // Correct rounding survives the scaling when both distances are normal doubles.
  if (!(rs.distance == 0 || (rs.distance >= std::numeric_limits<double>::min() && d >= std::numeric_limits<double>::min() && d < kInf)))
    return false;
  rs.distance = d;
  rs.point = {std::ldexp(rs.point.x, e), std::ldexp(rs.point.y, e), std::ldexp(rs.point.z, e)};
  r = rs;
  return true;
}

/// The query; `hint`: a slot whose triangle is likely near p (the previous point's answer in a
/// batch), for the first bound only (the answer does not depend on it).
ClosestPoint query(const DistanceTree& t, const Vec3<double>& p, std::uint32_t hint) {
  ClosestPoint r;
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return r;
  if (t.nodes.empty()) {
    r.distance = kInf;
    return r;
  }
  thread_local std::vector<NearCandidate> cands;
  cands.clear();
  Search s{t, p, cands};
  thread_local std::vector<DistanceVisit> visited;
  visited.clear();
  bool complete = true;
  s.U = first_pass(t, p, hint, visited, complete);
  // Squares beyond the double range (over- or underflow): the scaled copy, if there is one.
  if (!(s.U >= 0x1p-900 && s.U <= 0x1p+900) && t.scaled) {
    if (query_scaled(t, p, r)) return r;
    // The scaled query reused this thread's buffers: the first pass again.
    cands.clear(), visited.clear(), complete = true;
    s.U = first_pass(t, p, kNoSlot, visited, complete);
  }
  if (!(s.U < kInf)) s.U = kInf;  // NaN from overflow: the ball pass decides (or goes exact)
  if (complete && s.U < kInf) {
    // The visited triangles within the bound by their box, then by the lower bound along the
    // direction to their upper bound's point; nearest first.
    std::size_t kept = 0;
    const bool lower = !(distance_ablation() & kAblateLower);
    for (const DistanceVisit& v : visited)
      if (!lower && v.lb <= s.U) {
        visited[kept++] = v;
      } else if (v.lb <= s.U) {
        const double lb = lower_bound_along(t.tris[v.slot], p, v.dir);
        if (lb <= s.U) visited[kept++] = {v.slot, lb, v.dir};
      }
    visited.resize(kept);
    std::sort(visited.begin(), visited.end(), [](const DistanceVisit& a, const DistanceVisit& b) { return a.lb < b.lb; });
    for (const DistanceVisit& l : visited) {
      if (l.lb > s.U) break;
      s.triangle(l.slot);
      if (s.extreme) break;
    }
  } else {
    s.run();
  }
  if ((s.extreme || !(s.U < kInf)) && query_scaled(t, p, r)) return r;  // (the buffers are not read after)
  if (s.extreme || !(s.U < kInf)) {
    r = exact_search(t, p);
    r.stage = DistanceStage::extreme;
    return r;
  }
  // The features that can attain the least value.
  const NearCandidate* first = nullptr;
  bool ambiguous = false;
  std::uint32_t best_id = 0xffffffffu;
  const NearCandidate* best = nullptr;
  for (const NearCandidate& c : cands) {
    if (c.lo > s.U) continue;
    if (!c.sure) ambiguous = true;
    if (!first) first = &c;
    else if (!same_feature(t, *first, c)) ambiguous = true;
    if (t.ids[c.slot] < best_id) best_id = t.ids[c.slot], best = &c;
  }
  if (!first) {  // no feature within the bound: cannot happen when the bounds hold; decided exactly
    r = exact_search(t, p);
    r.stage = DistanceStage::extreme;
    return r;
  }
  if (ambiguous) {
    thread_local std::vector<std::uint32_t> slots;
    slots.clear();
    for (const NearCandidate& c : cands)
      if (c.lo <= s.U) slots.push_back(c.slot);
    std::sort(slots.begin(), slots.end());
    slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
    r = exact_select(t, p, slots.data(), slots.size());
    r.stage = DistanceStage::selection;
    return r;
  }
  r.triangle = best_id;
  fill_point(t, p, *best, r);
  r.stage = DistanceStage::filter;
  if (best->hi == 0) {
    r.distance = 0;
    return r;
  }
  // The rounding: the double interval, then double-double, then rationals.
  const double mid = (best->lo + best->hi) * 0.5;
  const BD bd{mid, (best->hi - best->lo) * 0.5 * kUp + mid * 0x1p-52};
  if (round_sqrt_ball(bd.x, bd.r, r.distance)) return r;
  const BQ bq = feature_value<BQ>(t.tris[best->slot], p, best->kind, best->k);
  if (bq.r < kInf && round_sqrt_ball(bq.x, bq.r, r.distance)) return r;
  r = exact_select(t, p, &best->slot, 1);  // the distance, point and weights from the rationals
  r.stage = DistanceStage::rounding;
  return r;
}

}  // namespace
}  // namespace scene::detail

namespace scene::detail {
namespace {
std::atomic<unsigned> ablation{0};
}  // namespace
void set_distance_ablation(unsigned flags) { ablation.store(flags, std::memory_order_relaxed); }
unsigned distance_ablation() { return ablation.load(std::memory_order_relaxed); }

const DistanceTree& distance_tree(const ExactMeshState& s) {
  std::call_once(s.distance_once, [&] {
    s.distance = std::make_shared<const DistanceTree>(build_distance_tree(s.vertices, s.triangles));
  });
  return *s.distance;
}
ClosestPoint distance_query(const DistanceTree& t, const Vec3<double>& p, std::uint32_t hint) { return query(t, p, hint); }
}  // namespace scene::detail

ClosestPoint ExactMesh::closest_point(const Vec3<double>& p, bool with_side) const {
  ClosestPoint r = scene::detail::query(scene::detail::distance_tree(*s_), p);
  if (with_side && r.distance == r.distance) r.side = r.distance == 0 ? Side::surface : contains(p);
  return r;
}

double ExactMesh::distance(const Vec3<double>& p) const { return scene::detail::query(scene::detail::distance_tree(*s_), p).distance; }

double ExactMesh::signed_distance(const Vec3<double>& p) const { return closest_point(p, true).signed_distance(); }

}  // namespace rayproof
