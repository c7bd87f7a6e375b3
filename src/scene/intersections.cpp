// Self-intersections and contact pairs (rayproof/scene/intersections.h, docs/intersect.md): a BVH
// over the triangles' float boxes rounded outwards, descended against itself (one mesh) or queried
// with each triangle's box of the other mesh (two meshes); each candidate decided by exact signs
// and the certified triangle/triangle tests.
#include "rayproof/scene/intersections.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <string>

#include "exact/orient_exact.h"
#include "rayproof/bvh_build.h"
#include "rayproof/certified/tritri.h"
#include "scene/batch_threads.h"

namespace rayproof {

namespace {

/// A mesh's triangles as packed doubles, their boxes and the tree over them.
struct PairMesh {
  std::vector<Vec3<double>> v;          ///< three vertices per triangle
  std::vector<std::uint32_t> idx;       ///< three vertex indices per triangle
  std::vector<BvhBox> box;              ///< per triangle, rounded outwards
  std::vector<std::uint8_t> zero_area;  ///< per triangle: collinear or coincident vertices (exact)
  Bvh bvh;
  [[nodiscard]] std::size_t size() const { return box.size(); }
  [[nodiscard]] Triangle<double> tri(std::size_t t) const { return {v[3 * t], v[3 * t + 1], v[3 * t + 2]}; }
};

Vec3<double> vertex_at(const VertexArray& va, std::size_t k) {
  const auto* p = static_cast<const unsigned char*>(va.data) + k * va.stride;
  if (va.is_double) {
    double c[3];
    std::memcpy(c, p, sizeof c);
    return {c[0], c[1], c[2]};
  }
  float c[3];
  std::memcpy(c, p, sizeof c);
  return {double(c[0]), double(c[1]), double(c[2])};
}

bool zero_area(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c) {
  for (int k = 0; k < 3; ++k) {
    const int u = (k + 1) % 3, w = (k + 2) % 3;
    if (certified::orient2d_exact(a[u], a[w], b[u], b[w], c[u], c[w]) != 0) return false;
  }
  return true;
}

template <class ForEach>
PairMesh load(const char* what, const VertexArray& va, const IndexArray& ia, bool with_tree, ForEach&& for_each) {
  if (ia.triangles > 0 && ia.data == nullptr) throw MeshInputError(std::string(what) + ": no index data");
  if (ia.triangles > 0 && va.count > 0 && va.data == nullptr) throw MeshInputError(std::string(what) + ": no vertex data");
  if (ia.triangles >= 0xffffffffu) throw MeshInputError(std::string(what) + ": too many triangles");
  PairMesh m;
  const std::size_t n = ia.triangles;
  m.v.resize(3 * n), m.idx.resize(3 * n), m.box.resize(n), m.zero_area.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(reinterpret_cast<const unsigned char*>(ia.data) + t * ia.stride);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t x = row[k];
      if (x >= va.count)
        throw MeshInputError(std::string(what) + ": triangle " + std::to_string(t) + " has vertex index " +
                            std::to_string(x) + " outside [0, " + std::to_string(va.count) + ")");
      const Vec3<double> p = vertex_at(va, x);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw MeshInputError(std::string(what) + ": vertex " + std::to_string(x) + " (of triangle " + std::to_string(t) +
                            ") has a NaN or infinite coordinate");
      m.idx[3 * t + k] = x, m.v[3 * t + k] = p;
      m.box[t].extend(p);
    }
  }
  for_each(n, [&](std::size_t t) { m.zero_area[t] = zero_area(m.v[3 * t], m.v[3 * t + 1], m.v[3 * t + 2]); });
  if (with_tree && n > 0) m.bvh = build_bvh(std::span<const BvhBox>(m.box), std::span<const Vec3<float>>(), {}, for_each);
  return m;
}

bool overlap(const BvhBox& a, const BvhBox& b) {
  return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] && a.lo[2] <= b.hi[2] &&
         b.lo[2] <= a.hi[2];
}

/// Calls f(j) for every triangle j of `tree` whose box overlaps `q`, in no particular order.
template <class F>
void query(const PairMesh& tree, const BvhBox& q, std::vector<std::uint32_t>& stack, F&& f) {
  if (tree.bvh.empty()) return;
  const auto& nodes = tree.bvh.nodes;
  stack.clear();
  stack.push_back(0);
  while (!stack.empty()) {
    const BvhNode& node = nodes[stack.back()];
    stack.pop_back();
    if (!overlap(node.box, q)) continue;
    if (node.is_leaf()) {
      for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
        const std::uint32_t j = tree.bvh.prim_ids[k];
        if (overlap(tree.box[j], q)) f(j);
      }
    } else {
      stack.push_back(node.index + 1);
      stack.push_back(node.index);
    }
  }
}

/// All three points strictly on one side of the plane of (p0, p1, p2) (exact signs).
bool one_side(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2, const Vec3<double>& x,
              const Vec3<double>& y, const Vec3<double>& z) {
  const int s = certified::orient3d_exact(p0, p1, p2, x);
  if (s == 0) return false;
  return certified::orient3d_exact(p0, p1, p2, y) == s && certified::orient3d_exact(p0, p1, p2, z) == s;
}

/// The segment (x, y) strictly on one side of the plane of (p0, p1, p2) (exact signs).
bool segment_off_plane(const Vec3<double>& p0, const Vec3<double>& p1, const Vec3<double>& p2, const Vec3<double>& x,
                       const Vec3<double>& y) {
  const int s = certified::orient3d_exact(p0, p1, p2, x);
  return s != 0 && certified::orient3d_exact(p0, p1, p2, y) == s;
}

/// The closed segment [x, y] (x != y) meets the closed triangle t (positive area): the certified
/// classifier's segment test on exact signs (no zero-area proof of the segment as a triangle).
bool segment_meets(const Vec3<double>& x, const Vec3<double>& y, const Vec3<double>* t) {
  auto o3 = [](const Vec3<double>& p, const Vec3<double>& q, const Vec3<double>& r, const Vec3<double>& w) {
    return certified::orient3d_exact(p, q, r, w);
  };
  auto o2 = [](double au, double av, double bu, double bv, double pu, double pv) {
    return certified::orient2d_exact(au, av, bu, bv, pu, pv);
  };
  certified::tritri_detail::Signs<decltype(o3), decltype(o2)> sg{o3, o2};
  const Vec3<double> tri[3] = {t[0], t[1], t[2]};
  return certified::tritri_detail::segment_meets_triangle(sg, x, y, tri);
}

/// Whether triangles i and j (i != j, both of positive area) of one mesh intersect beyond the
/// vertices they share by index (the header's rule). Exact plane-side signs settle the common
/// cases first (apart, not coplanar); the certified tests decide the rest.
bool self_pair_intersects(const PairMesh& m, std::uint32_t i, std::uint32_t j) {
  const std::uint32_t* a = &m.idx[3 * i];
  const std::uint32_t* b = &m.idx[3 * j];
  const Vec3<double>* pa = &m.v[3 * i];
  const Vec3<double>* pb = &m.v[3 * j];
  int shared = 0, ka = -1, kb = -1, b_only = -1;
  for (int y = 0; y < 3; ++y) {
    bool in_a = false;
    for (int x = 0; x < 3; ++x)
      if (a[x] == b[y]) ++shared, ka = x, kb = y, in_a = true;
    if (!in_a) b_only = y;
  }
  if (shared == 0) {
    if (one_side(pa[0], pa[1], pa[2], pb[0], pb[1], pb[2]) || one_side(pb[0], pb[1], pb[2], pa[0], pa[1], pa[2]))
      return false;
    return certified::tritri_meets(m.tri(i), m.tri(j));
  }
  if (shared >= 2) {
    // Not coplanar: they meet in the shared edge alone.
    if (shared == 2 && certified::orient3d_exact(pa[0], pa[1], pa[2], pb[b_only]) != 0) return false;
    return certified::tritri(m.tri(i), m.tri(j)) == TriTri::coplanar_overlap;
  }
  // One shared vertex: a point in both other than it exists exactly when the edge of one opposite
  // the shared vertex meets the other triangle (the nearer of the two exits of a ray from the
  // shared vertex through such a point lies on an opposite edge and in both triangles).
  const Vec3<double>& a1 = pa[(ka + 1) % 3];
  const Vec3<double>& a2 = pa[(ka + 2) % 3];
  const Vec3<double>& b1 = pb[(kb + 1) % 3];
  const Vec3<double>& b2 = pb[(kb + 2) % 3];
  // The edge of b opposite v strictly on one side of a's plane puts all of b but v strictly on that
  // side: nothing beyond v in common (two signs settle most pairs of a smooth mesh); likewise a.
  if (segment_off_plane(pa[0], pa[1], pa[2], b1, b2) || segment_off_plane(pb[0], pb[1], pb[2], a1, a2)) return false;
  return segment_meets(b1, b2, pa) || segment_meets(a1, a2, pb);
}

/// Two nodes of one tree whose triangles are paired (a == b: the pairs within one node).
struct NodePair {
  std::uint32_t a, b;
};
/// Levels of the simultaneous descent expanded on the calling thread into tasks (each level about
/// triples their number: a few hundred tasks for the threads).
constexpr int kTaskLevels = 6;

/// One step of the descent of the tree against itself: a node with itself gives its children with
/// themselves and with each other; two nodes with overlapping boxes give the larger one's children
/// with the other; leaves give their triangles' pairs whose boxes overlap (each unordered pair of
/// distinct triangles once over the whole descent).
template <class Push, class Emit>
void self_step(const PairMesh& m, NodePair t, Push&& push, Emit&& emit) {
  const auto& nodes = m.bvh.nodes;
  const auto& ids = m.bvh.prim_ids;
  const BvhNode& A = nodes[t.a];
  if (t.a == t.b) {
    if (A.is_leaf()) {
      for (std::uint32_t k = A.index; k < A.index + A.count; ++k)
        for (std::uint32_t l = k + 1; l < A.index + A.count; ++l)
          if (overlap(m.box[ids[k]], m.box[ids[l]])) emit(ids[k], ids[l]);
    } else {
      push(NodePair{A.index, A.index}), push(NodePair{A.index + 1, A.index + 1}), push(NodePair{A.index, A.index + 1});
    }
    return;
  }
  const BvhNode& B = nodes[t.b];
  if (!overlap(A.box, B.box)) return;
  if (A.is_leaf() && B.is_leaf()) {
    for (std::uint32_t k = A.index; k < A.index + A.count; ++k) {
      const BvhBox& bk = m.box[ids[k]];
      if (!overlap(bk, B.box)) continue;
      for (std::uint32_t l = B.index; l < B.index + B.count; ++l)
        if (overlap(bk, m.box[ids[l]])) emit(ids[k], ids[l]);
    }
  } else if (B.is_leaf() || (!A.is_leaf() && A.box.half_area() >= B.box.half_area())) {
    push(NodePair{A.index, t.b}), push(NodePair{A.index + 1, t.b});
  } else {
    push(NodePair{t.a, B.index}), push(NodePair{t.a, B.index + 1});
  }
}

/// Triangles in blocks of a fixed size (not of the thread count): each block's pairs are found on
/// one thread in order, and the blocks are joined in order, so the output does not depend on threads.
constexpr std::size_t kBlock = 512;

template <class PerTriangle>
std::vector<TrianglePair> run_blocks(std::size_t n, int threads, PerTriangle&& per_triangle) {
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<TrianglePair>> out(blocks);
  scene::detail::for_each_batch_range(blocks, threads, 2, 1, [&](std::size_t b0, std::size_t b1) {
    std::vector<std::uint32_t> stack;
    stack.reserve(128);
    std::vector<TrianglePair> row;
    for (std::size_t b = b0; b < b1; ++b)
      for (std::size_t t = b * kBlock; t < std::min(n, (b + 1) * kBlock); ++t) {
        row.clear();
        per_triangle(static_cast<std::uint32_t>(t), stack, row);
        std::sort(row.begin(), row.end());
        out[b].insert(out[b].end(), row.begin(), row.end());
      }
  });
  std::size_t total = 0;
  for (const auto& o : out) total += o.size();
  std::vector<TrianglePair> pairs;
  pairs.reserve(total);
  for (const auto& o : out) pairs.insert(pairs.end(), o.begin(), o.end());
  return pairs;
}

auto parallel(int threads) {
  return [threads](std::size_t n, auto&& f) {
    scene::detail::for_each_batch_range(n, threads, 1024, 256, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) f(i);
    });
  };
}

}  // namespace

std::vector<TrianglePair> self_intersections(const VertexArray& vertices, const IndexArray& indices,
                                             const IntersectOptions& opt) {
  const PairMesh m = load("mesh", vertices, indices, true, parallel(opt.threads));
  std::vector<TrianglePair> pairs;
  for (std::uint32_t i = 0; i < m.size(); ++i)
    if (m.zero_area[i]) pairs.push_back({i, i, opt.classes ? TriTri::degenerate : TriTri::invalid});
  const auto test = [&](std::uint32_t p, std::uint32_t q, std::vector<TrianglePair>& out) {
    const std::uint32_t i = std::min(p, q), j = std::max(p, q);
    if (m.zero_area[i] || m.zero_area[j] || !self_pair_intersects(m, i, j)) return;
    out.push_back({i, j, opt.classes ? certified::tritri(m.tri(i), m.tri(j)) : TriTri::invalid});
  };
  if (!m.bvh.empty()) {
    // The top levels one after the other, into tasks; then the tasks on the threads.
    std::vector<NodePair> tasks{{0, 0}}, next;
    for (int level = 0; level < kTaskLevels && !tasks.empty(); ++level) {
      next.clear();
      for (const NodePair& t : tasks)
        self_step(m, t, [&](NodePair c) { next.push_back(c); }, [&](std::uint32_t p, std::uint32_t q) { test(p, q, pairs); });
      tasks.swap(next);
    }
    std::vector<std::vector<TrianglePair>> found(tasks.size());
    scene::detail::for_each_batch_range(tasks.size(), opt.threads, 2, 1, [&](std::size_t t0, std::size_t t1) {
      std::vector<NodePair> stack;
      for (std::size_t t = t0; t < t1; ++t) {
        stack.assign(1, tasks[t]);
        while (!stack.empty()) {
          const NodePair top = stack.back();
          stack.pop_back();
          self_step(m, top, [&](NodePair c) { stack.push_back(c); },
                    [&](std::uint32_t p, std::uint32_t q) { test(p, q, found[t]); });
        }
      }
    });
    for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<TrianglePair> intersecting_pairs(const MeshArrays& a, const MeshArrays& b, const IntersectOptions& opt) {
  const PairMesh ma = load("first mesh", a.vertices, a.indices, false, parallel(opt.threads));
  const PairMesh mb = load("second mesh", b.vertices, b.indices, true, parallel(opt.threads));
  return run_blocks(ma.size(), opt.threads, [&](std::uint32_t i, std::vector<std::uint32_t>& stack, auto& row) {
    const Triangle<double> ti = ma.tri(i);
    query(mb, ma.box[i], stack, [&](std::uint32_t j) {
      if (!certified::tritri_meets(ti, mb.tri(j))) return;
      row.push_back({i, j, opt.classes ? certified::tritri(ti, mb.tri(j)) : TriTri::invalid});
    });
  });
}

}  // namespace rayproof
