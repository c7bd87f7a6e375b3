// The winding rule's fast path. Let c be the mesh's boundary chain: every welded edge with its net
// orientation (uses a->b minus uses b->a) when nonzero. It is a cycle (the boundary of a 2-chain),
// so each connected component of it bounds a cone to any apex O: the cap triangles (b, a, O), one per
// net use of a->b. Mesh + caps is then an oriented closed 2-cycle, whose winding number W(p) is an
// exact integer (the perturbed-ray count of contains.cpp), and since solid angles add,
//     w_mesh(p) = W(p) - w_caps(p).
// The caps are small (the holes' cones, apex at each component's centroid), so their far-field
// bounds are small and w_caps is bounded after few nodes: the side is decided at about the cost of
// contains on a closed mesh. Where this cannot decide (p on a cap or on the surface, or w within
// the caps' bound of 1/2 after every cap triangle is evaluated directly) the full tree decides
// (winding_tree.cpp).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <unordered_map>

#include "scene/contains_state.h"

namespace rayproof::detail {

namespace {

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

bool in_box(const ContainsState& s, const Vec3<double>& p) {
  return s.lo.x <= p.x && p.x <= s.hi.x && s.lo.y <= p.y && p.y <= s.hi.y && s.lo.z <= p.z && p.z <= s.hi.z;
}

}  // namespace

void build_caps(ContainsState& s) {
  const std::vector<std::uint32_t> id = weld(s.vertices);
  std::unordered_map<std::uint64_t, int> balance;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = id[t[k]], b = id[t[(k + 1) % 3]];
      if (a == b) continue;
      const std::uint64_t key = a < b ? (std::uint64_t(a) << 32 | b) : (std::uint64_t(b) << 32 | a);
      balance[key] += a < b ? 1 : -1;
    }
  std::vector<std::uint32_t> parent(s.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  struct Edge {
    std::uint32_t lo, hi;
    int net;
  };
  std::vector<Edge> boundary;
  for (const auto& [key, net] : balance)
    if (net != 0) {
      const auto lo = std::uint32_t(key >> 32), hi = std::uint32_t(key);
      boundary.push_back({lo, hi, net});
      parent[find(parent, lo)] = find(parent, hi);
    }
  if (boundary.empty()) return;  // oriented and closed: the tree alone
  std::sort(boundary.begin(), boundary.end(), [](const Edge& x, const Edge& y) { return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi; });
  // One apex per component: the mean of its vertices.
  std::unordered_map<std::uint32_t, std::uint32_t> apex;  // component root -> apex vertex
  std::unordered_map<std::uint32_t, std::array<double, 4>> sums;
  std::vector<char> seen(s.vertices.size(), 0);
  for (const Edge& e : boundary)
    for (std::uint32_t v : {e.lo, e.hi})
      if (!seen[v]) {
        seen[v] = 1;
        auto& acc = sums[find(parent, v)];
        acc[0] += s.vertices[v].x, acc[1] += s.vertices[v].y, acc[2] += s.vertices[v].z, acc[3] += 1;
      }
  auto st = std::make_unique<ContainsState>();
  std::vector<Vec3<double>> verts = s.vertices;
  std::vector<std::array<std::uint32_t, 3>> tris = s.triangles, caps;
  for (const auto& [root, acc] : sums) {
    apex[root] = std::uint32_t(verts.size());
    verts.push_back({acc[0] / acc[3], acc[1] / acc[3], acc[2] / acc[3]});
  }
  for (const Edge& e : boundary) {
    const std::uint32_t o = apex[find(parent, e.lo)];
    // net uses lo -> hi are cancelled by (hi, lo, O); net uses hi -> lo by (lo, hi, O).
    const std::array<std::uint32_t, 3> cap = e.net > 0 ? std::array<std::uint32_t, 3>{e.hi, e.lo, o}
                                                       : std::array<std::uint32_t, 3>{e.lo, e.hi, o};
    for (int k = 0; k < std::abs(e.net); ++k) caps.push_back(cap);
  }
  tris.insert(tris.end(), caps.begin(), caps.end());
  try {
    load_contains_state(*st, VertexArray(&verts[0].x, verts.size()), IndexArray{tris.front().data(), tris.size()},
                        ContainsRule::nonzero);
  } catch (const std::exception&) {
    return;  // not closed after all (cannot happen for a cycle; the full tree answers then)
  }
  s.caps = std::make_unique<WindingTree>(st->vertices, caps);
  s.capped = std::move(st);
}

Side winding_side(const ContainsState& s, const Vec3<double>& p) {
  if (!s.capped) return s.tree->side(p);
  std::int32_t W = 0;
  if (in_box(*s.capped, p)) {
    const PointQuery q = query_point(*s.capped, p);
    if (q.surface) return s.tree->side(p);  // on the mesh (surface) or on a cap
    W = q.winding;
  }
  const WindingValue c = s.caps->value_against(p, double(W));
  if (!c.surface) {
    // W - c.w rounds once (2^-53 relative to |W| + 1 at most, as |c.w| <= |W| + 1 where it matters).
    const double w = double(W) - c.w;
    if (std::fabs(w - 0.5) > c.bound * (1 + 0x1p-40) + 0x1p-50 * (std::fabs(double(W)) + 1))
      return w > 0.5 ? Side::inside : Side::outside;
  }
  return s.tree->side(p);
}

}  // namespace rayproof::detail
