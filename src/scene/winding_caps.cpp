// The winding rule's fast path. Let c be the mesh's boundary chain: every welded edge with its net
// orientation (uses a->b minus uses b->a) when nonzero. It is a cycle (the boundary of a 2-chain),
// so it bounds a 2-chain made of caps: hierarchical fans over its closed walks (walk_caps below;
// the default), or a cone to an apex O per connected component (the cap triangles (b, a, O), one
// per net use of a->b; WindingTuning::compact_caps = false). Mesh + caps is then an oriented closed
// 2-cycle, whose winding number W(p) is an exact integer (the perturbed-ray count of contains.cpp),
// and since solid angles add,
//     w_mesh(p) = W(p) - w_caps(p).
// The caps are small (they span the holes), so their bounds are small and w_caps is bounded after
// few nodes: the side is decided at about the cost of contains on a closed mesh. Where this cannot
// decide (p on a cap or on the surface, or w within the caps' bound of 1/2 after every cap triangle
// is evaluated directly) the full tree decides (winding_tree.cpp).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

#include "scene/exact_mesh_state.h"

namespace rayproof::scene::detail {

namespace {

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// The capped mesh (mesh + caps, closed) and the caps' tree.
void finish_caps(ExactMeshState& s, std::unique_ptr<ExactMeshState> st, const std::vector<Vec3<double>>& verts,
                 std::vector<std::array<std::uint32_t, 3>> tris, std::vector<std::array<std::uint32_t, 3>> caps) {
  if (caps.empty()) return;
  tris.insert(tris.end(), caps.begin(), caps.end());
  try {
    load_exact_mesh_state(*st, VertexArray(&verts[0].x, verts.size()), IndexArray{tris.front().data(), tris.size()},
                        ContainsRule::nonzero);
  } catch (const std::exception&) {
    return;  // not closed after all (cannot happen for a cycle; the full tree answers then)
  }
  s.caps = std::make_unique<WindingTree>(st->vertices, caps, winding_tuning().caps_leaf);
  s.caps_field = winding_tuning().caps_field;
  s.capped = std::move(st);
}

/// Caps made of compact triangles (the default; WindingTuning::compact_caps): the cap edges (each
/// boundary edge reversed, as often as its net use) split into closed walks, each walk spanned by
/// a hierarchical fan: triangles over every two consecutive walk edges, then the same over the
/// walk of every other vertex, until three remain. The triangles' boundary, as a chain, is the walk
/// (each chord is used once in each direction), so mesh + caps is again closed. Most triangles are
/// as small as the hole's edges, so the tree's balls are tight; a cone from one apex (the former
/// caps) is all slivers as long as the hole is wide, whose balls hold every point near the hole.
std::vector<std::array<std::uint32_t, 3>> walk_caps(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& cap_edges) {
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> out;
  std::vector<std::uint32_t> starts;
  for (const auto& [a, b] : cap_edges) {
    auto& o = out[a];
    if (o.empty()) starts.push_back(a);
    o.push_back(b);
  }
  std::vector<std::array<std::uint32_t, 3>> caps;
  std::vector<std::uint32_t> walk, next;
  for (const std::uint32_t s : starts)
    while (!out[s].empty()) {
      // A closed walk from s: each vertex entered has an unused out edge (in = out everywhere).
      walk.assign(1, s);
      for (std::uint32_t cur = s;;) {
        auto& o = out[cur];
        if (o.empty()) throw std::logic_error("walk_caps: the boundary chain is not a cycle");  // cannot happen
        const std::uint32_t nxt = o.back();
        o.pop_back();
        if (nxt == s) break;
        walk.push_back(nxt), cur = nxt;
      }
      while (walk.size() >= 3) {
        if (walk.size() == 3) {
          caps.push_back({walk[0], walk[1], walk[2]});
          break;
        }
        next.clear();
        std::size_t i = 0;
        for (; i + 2 <= walk.size(); i += 2) {
          caps.push_back({walk[i], walk[i + 1], walk[(i + 2) % walk.size()]});
          next.push_back(walk[i]);
        }
        if (i < walk.size()) next.push_back(walk[i]);  // odd: the last vertex stays
        walk.swap(next);
      }
      // A walk of two vertices (a -> b -> a) bounds nothing.
    }
  return caps;
}

}  // namespace

void build_caps(ExactMeshState& s) {
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
  auto st = std::make_unique<ExactMeshState>();
  std::vector<std::array<std::uint32_t, 3>> tris = s.triangles, caps;
  if (winding_tuning().compact_caps) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> cap_edges;
    for (const Edge& e : boundary)  // net uses lo -> hi are cancelled by hi -> lo, and the reverse
      for (int k = 0; k < std::abs(e.net); ++k) cap_edges.push_back(e.net > 0 ? std::pair{e.hi, e.lo} : std::pair{e.lo, e.hi});
    caps = walk_caps(cap_edges);
    return finish_caps(s, std::move(st), s.vertices, std::move(tris), std::move(caps));
  }
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
  std::vector<Vec3<double>> verts = s.vertices;
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
  finish_caps(s, std::move(st), verts, std::move(tris), std::move(caps));
}

void prepare_caps_field(const ExactMeshState& s, const std::byte* xyz, std::size_t n, std::size_t stride) {
  // Checked before the sample is drawn: batches on meshes without a field copy nothing.
  if (!s.caps || !s.capped || s.caps->triangle_count() < 16 || !s.caps_field ||
      s.field.load(std::memory_order_acquire))
    return;
  std::call_once(s.field_once, [&] {
    // The sample: at most 65536 of the finite points, evenly strided.
    std::vector<Vec3<double>> sample;
    const std::size_t step = (n + 65535) / 65536;
    for (std::size_t i = 0; i < n; i += step) {
      Vec3<double> p;
      std::memcpy(&p, xyz + i * stride, sizeof p);
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) sample.push_back(p);
    }
    // 8 cells per cap triangle, from 4096 to 65536, spent where the sample's points are: about
    // 0.1 s for the 1079 cap triangles of elephant-with-holes (docs/contains.md).
    const std::size_t cells = std::clamp<std::size_t>(8 * s.caps->triangle_count(), 4096, 65536);
    s.field_owned = std::make_unique<CapsField>(*s.caps, s.capped->lo, s.capped->hi, cells, sample);
    s.field.store(s.field_owned.get(), std::memory_order_release);
  });
}

Side winding_side(const ExactMeshState& s, const Vec3<double>& p) {
  if (!s.capped) return s.tree->side(p);
  std::int32_t W = 0;
  if (in_box(*s.capped, p)) {
    const PointQuery q = query_point(*s.capped, p);
    if (q.surface) return s.tree->side(p);  // on the mesh (surface) or on a cap
    W = q.winding;
    double w0 = 0, e = 0;
    const CapsField* f = s.field.load(std::memory_order_acquire);
    if (f && f->value(p, &w0, &e)) {
      const double w = double(W) - w0;  // one rounding, covered by the 2^-50 term
      if (std::fabs(w - 0.5) > e * (1 + 0x1p-40) + 0x1p-50 * (std::fabs(double(W)) + std::fabs(w0) + 1))
        return w > 0.5 ? Side::inside : Side::outside;
    }
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

}  // namespace rayproof::scene::detail
