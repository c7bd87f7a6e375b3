// Self-intersections and contact pairs (rayproof/scene/intersections.h, docs/intersect.md): a BVH
// over the triangles' float boxes rounded outwards, descended against itself (one mesh) or queried
// with each triangle's box of the other mesh (two meshes); each candidate decided by exact signs
// and the certified triangle/triangle tests.
#include "rayproof/scene/intersections.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <span>
#include <new>
#include <string>
#include <type_traits>

#include <sys/mman.h>

#include "exact/orient_exact.h"
#include "rayproof/bvh.h"
#include "rayproof/certified/tritri.h"
#include "scene/batch_threads.h"

namespace rayproof {

namespace {

/// A box with float bounds rounded outwards (no initialisers: arrays of them are not zeroed first).
struct Box {
  float lo[3], hi[3];
  void extend(const Box& b) {
    for (int k = 0; k < 3; ++k) lo[k] = b.lo[k] < lo[k] ? b.lo[k] : lo[k], hi[k] = b.hi[k] > hi[k] ? b.hi[k] : hi[k];
  }
  [[nodiscard]] float half_area() const {
    const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
  }
};

/// A node of the overlap tree: a box, and either two children (at index, index + 1) or a leaf's
/// run of slots [index, index + count) (the triangles are stored in the tree's order).
struct Node {
  Box box;
  std::uint32_t index, count;
  [[nodiscard]] bool is_leaf() const { return count != 0; }
};

/// Memory of at least this many bytes is asked for in transparent huge pages (2 MiB): a large
/// mesh's arrays take a hundred MB, and their first touch in 4 KiB pages (one fault each) cost about
/// a tenth of the whole run on a 1.31M-triangle mesh.
constexpr std::size_t kHugeBytes = std::size_t(1) << 20;

/// Uninitialised memory aligned to 64 bytes (2 MiB and advised into huge pages from kHugeBytes).
struct RawMemory {
  struct Free {
    void operator()(void* q) const { std::free(q); }
  };
  std::unique_ptr<void, Free> p;
  void allocate(std::size_t bytes) {
    p.reset();
    if (bytes == 0) return;
    const std::size_t align = bytes >= kHugeBytes ? std::size_t(2) << 20 : 64;
    bytes = (bytes + align - 1) / align * align;
    p.reset(std::aligned_alloc(align, bytes));
    if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    if (align > 64) madvise(p.get(), bytes, MADV_HUGEPAGE);  // advice only: failure changes nothing
#endif
  }
};

/// An array of a trivial type left uninitialised (every element is written before it is read).
template <class T>
struct Buffer {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T> && alignof(T) <= 64);
  RawMemory mem;
  T* p = nullptr;
  std::size_t n = 0;
  void resize(std::size_t count) {
    mem.allocate(count * sizeof(T));
    p = static_cast<T*>(mem.p.get()), n = count;
  }
  [[nodiscard]] std::size_t size() const { return n; }
  T& operator[](std::size_t i) { return p[i]; }
  const T& operator[](std::size_t i) const { return p[i]; }
};

/// Two sibling nodes on one cache line (children are allocated in pairs at even indices).
struct alignas(64) NodeLine {
  Node n[2];
};

/// A mesh's triangles in the tree's order (slots): vertex indices, boxes, zero-area flags, and
/// the used vertices as packed doubles, renumbered in the order the slots first use them (so the
/// triangles of one leaf, and of nearby leaves, read nearby memory). The renumbering is one to
/// one on the used vertices, so two slots share a renumbered index exactly when they share an
/// input index.
struct PairMesh {
  std::size_t n = 0;
  Buffer<Vec3<double>> vertices;       ///< the used vertices, renumbered
  Buffer<std::uint32_t> idx;           ///< three renumbered vertex indices per slot
  Buffer<std::uint32_t> id;            ///< the input's triangle number of each slot
  Buffer<Box> box;                     ///< per slot
  Buffer<std::uint8_t> zero_area;      ///< per slot: collinear or coincident vertices (exact)
  Buffer<NodeLine> lines;              ///< the tree's nodes, two per line (none without a tree)
  Node* nodes = nullptr;               ///< node k: lines[k / 2].n[k % 2]; 0 the root (1 unused)
  [[nodiscard]] bool has_tree() const { return nodes != nullptr; }
  [[nodiscard]] std::size_t size() const { return n; }
  [[nodiscard]] const Vec3<double>& vertex(std::uint32_t x) const { return vertices[x]; }
  void corners(std::size_t s, Vec3<double>* out) const {
    for (int k = 0; k < 3; ++k) out[k] = vertex(idx[3 * s + k]);
  }
  [[nodiscard]] Triangle<double> tri(std::size_t s) const {
    return {vertex(idx[3 * s]), vertex(idx[3 * s + 1]), vertex(idx[3 * s + 2])};
  }
};
static_assert(sizeof(Vec3<double>) == 24 && sizeof(Node) == 32 && sizeof(NodeLine) == 64);

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

/// The plane of a triangle (p0, p1, p2) as orient3d's filter uses it: the minors of (p1 - p0) and
/// (p2 - p0) and their absolute sums, so that side() computes bit for bit the double value and
/// bound of orient::orient3d(p0, p1, p2, x) with a third of its products.
struct Plane {
  double nx, ny, nz;  ///< m1 - m2, m3 - m4, m5 - m6
  double sx, sy, sz;  ///< |m1| + |m2|, |m3| + |m4|, |m5| + |m6|
  bool filter;        ///< the edge differences are in the filter's exponent window
};

Plane plane_of(const Vec3<double>& a, const Vec3<double>& b, const Vec3<double>& c) {
  // The operations of orient::orient3d(a, b, c, .) on u = b - a, v = c - a, in its order.
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const double m1 = uy * vz, m2 = uz * vy, m3 = uz * vx, m4 = ux * vz, m5 = ux * vy, m6 = uy * vx;
  return {m1 - m2,
          m3 - m4,
          m5 - m6,
          std::fabs(m1) + std::fabs(m2),
          std::fabs(m3) + std::fabs(m4),
          std::fabs(m5) + std::fabs(m6),
          certified::in_range<-480, 1023>(ux, uy, uz, vx, vy, vz)};
}

/// The exact predicate, out of line: the filter's path below stays small enough to inline.
[[gnu::noinline]] int side_exact(const Vec3<double>* t, const Vec3<double>& x) {
  return certified::orient3d_exact(t[0], t[1], t[2], x);
}

/// The exact sign of orient3d(t[0], t[1], t[2], x), P the plane of t: orient3d's filter on the
/// stored minors (the same double value and bound), else the exact predicate.
inline int side(const Plane& P, const Vec3<double>* t, const Vec3<double>& x) {
  if (P.filter) {
    const double wx = x.x - t[0].x, wy = x.y - t[0].y, wz = x.z - t[0].z;
    const double det = wx * P.nx + wy * P.ny + wz * P.nz;
    const double perm = P.sx * std::fabs(wx) + P.sy * std::fabs(wy) + P.sz * std::fabs(wz);
    if (perm > orient::detail::kTiny && std::fabs(det) > orient::detail::kO3dBound * perm &&
        certified::in_range<-480, 1023>(wx, wy, wz))
      return det > 0 ? 1 : -1;
  }
  return side_exact(t, x);
}

/// 30-bit Morton code of a grid cell (x, y, z < 1024).
std::uint32_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint32_t b) {
    b = (b | (b << 16)) & 0x030000ffu;
    b = (b | (b << 8)) & 0x0300f00fu;
    b = (b | (b << 4)) & 0x030c30c3u;
    b = (b | (b << 2)) & 0x09249249u;
    return b;
  };
  return (spread(x) << 2) | (spread(y) << 1) | spread(z);
}

/// Leaves hold up to this many triangles.
constexpr std::uint32_t kLeaf = 4;
static_assert(kLeaf * kLeaf <= 32, "a leaf pair's box tests are the bits of an unsigned");

/// Builds node `ni` over slots [first, last) of `key` (sorted, the Morton code in the high 32
/// bits): a leaf of up to kLeaf, else split where the codes' highest differing bit turns on (at the
/// middle when they are equal).
Box build_node(Node* nodes, std::uint32_t& used, const Buffer<Box>& box, const Buffer<std::uint64_t>& key,
               std::uint32_t ni, std::uint32_t first, std::uint32_t last) {
  if (last - first <= kLeaf) {
    Box b = box[first];
    for (std::uint32_t k = first + 1; k < last; ++k) b.extend(box[k]);
    nodes[ni] = Node{b, first, last - first};
    return b;
  }
  std::uint32_t split = first + (last - first) / 2;
  const std::uint32_t diff = std::uint32_t(key[first] >> 32) ^ std::uint32_t(key[last - 1] >> 32);
  if (diff != 0) {
    const std::uint64_t bit = std::uint64_t(0x80000000u >> std::countl_zero(diff)) << 32;
    split = static_cast<std::uint32_t>(
        std::partition_point(key.p + first, key.p + last, [&](std::uint64_t c) { return (c & bit) == 0; }) - key.p);
  }
  const std::uint32_t c = used;  // even: the two children share a line
  used += 2;
  Box b = build_node(nodes, used, box, key, c, first, split);
  b.extend(build_node(nodes, used, box, key, c + 1, split, last));
  nodes[ni] = Node{b, c, 0};
  return b;
}

template <class ForEach>
PairMesh load(const char* what, const VertexArray& va, const IndexArray& ia, bool with_tree, ForEach&& for_each) {
  if (ia.triangles > 0 && ia.data == nullptr) throw MeshInputError(std::string(what) + ": no index data");
  if (ia.triangles > 0 && va.count > 0 && va.data == nullptr) throw MeshInputError(std::string(what) + ": no vertex data");
  if (ia.triangles >= 0xffffffffu) throw MeshInputError(std::string(what) + ": too many triangles");
  const std::size_t n = ia.triangles;
  auto row = [&](std::size_t t) {
    return reinterpret_cast<const std::uint32_t*>(reinterpret_cast<const unsigned char*>(ia.data) + t * ia.stride);
  };
  PairMesh m;
  m.n = n;
  if (n == 0) return m;
  // The input checked in its order (the first bad triangle is the one reported); the bounds of the
  // used vertices for the Morton codes.
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t x = row(t)[k];
      if (x >= va.count)
        throw MeshInputError(std::string(what) + ": triangle " + std::to_string(t) + " has vertex index " +
                            std::to_string(x) + " outside [0, " + std::to_string(va.count) + ")");
      const Vec3<double> p = vertex_at(va, x);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw MeshInputError(std::string(what) + ": vertex " + std::to_string(x) + " (of triangle " + std::to_string(t) +
                            ") has a NaN or infinite coordinate");
      for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    }
  // The slots' order: by the Morton code of each triangle's centroid on a 1024^3 grid over the
  // bounds (radix sort, stable: equal codes keep the input's order); the input's order without a tree.
  Buffer<std::uint64_t> key;
  m.id.resize(n);
  if (with_tree) {
    key.resize(n);
    double scale[3];
    for (int c = 0; c < 3; ++c) scale[c] = hi[c] > lo[c] ? 1023.0 / (hi[c] - lo[c]) : 0.0;
    for_each(n, [&](std::size_t t) {
      std::uint32_t g[3];
      for (int c = 0; c < 3; ++c) {
        double sum = 0;
        for (int k = 0; k < 3; ++k) sum += vertex_at(va, row(t)[k])[c];
        const double f = (sum / 3 - lo[c]) * scale[c];
        g[c] = static_cast<std::uint32_t>(std::clamp(f, 0.0, 1023.0));
      }
      key[t] = (std::uint64_t(morton(g[0], g[1], g[2])) << 32) | t;
    });
    Buffer<std::uint64_t> tmp;
    tmp.resize(n);
    for (int shift = 32; shift < 62; shift += 10) {  // three passes of 10 bits
      std::vector<std::uint32_t> count(1025, 0);
      for (std::size_t t = 0; t < n; ++t) ++count[((key[t] >> shift) & 1023) + 1];
      for (int d = 0; d < 1024; ++d) count[d + 1] += count[d];
      for (std::size_t t = 0; t < n; ++t) tmp[count[(key[t] >> shift) & 1023]++] = key[t];
      std::swap(key, tmp);
    }
    for (std::size_t s = 0; s < n; ++s) m.id[s] = std::uint32_t(key[s]);
  } else {
    for (std::size_t s = 0; s < n; ++s) m.id[s] = static_cast<std::uint32_t>(s);
  }
  // The used vertices renumbered in the order the slots first use them, and copied so.
  m.idx.resize(3 * n), m.box.resize(n), m.zero_area.resize(n);
  {
    constexpr std::uint32_t kNone = 0xffffffffu;
    Buffer<std::uint32_t> number, used;
    number.resize(va.count), used.resize(std::min<std::size_t>(va.count, 3 * n));
    std::fill(number.p, number.p + va.count, kNone);
    std::uint32_t count = 0;
    for (std::size_t s = 0; s < n; ++s) {
      const std::uint32_t* r = row(m.id[s]);
      for (int k = 0; k < 3; ++k) {
        std::uint32_t& x = number[r[k]];
        if (x == kNone) x = count, used[count++] = r[k];
        m.idx[3 * s + k] = x;
      }
    }
    m.vertices.resize(count);
    for_each(count, [&](std::size_t x) { m.vertices[x] = vertex_at(va, used[x]); });
  }
  for_each(n, [&](std::size_t s) {
    Vec3<double> p[3];
    for (int k = 0; k < 3; ++k) p[k] = m.vertex(m.idx[3 * s + k]);
    // Rounding is monotone: the float bounds of the double bounds are those of the three corners'.
    Box b;
    for (int c = 0; c < 3; ++c) {
      b.lo[c] = bvh_float_down(std::min(std::min(p[0][c], p[1][c]), p[2][c]));
      b.hi[c] = bvh_float_up(std::max(std::max(p[0][c], p[1][c]), p[2][c]));
    }
    m.box[s] = b;
    m.zero_area[s] = zero_area(p[0], p[1], p[2]);
  });
  if (with_tree) {
    m.lines.resize(n + 1);  // at most 2n - 1 nodes, and the unused node 1
    m.nodes = m.lines.p[0].n;
    std::uint32_t used = 2;
    build_node(m.nodes, used, m.box, key, 0, 0, static_cast<std::uint32_t>(n));
  }
  return m;
}

/// The closed boxes overlap: six comparisons joined without a branch (whether two boxes of a
/// descent overlap is close to a coin toss, a branch per comparison mispredicts often).
bool overlap(const Box& a, const Box& b) {
  return (a.lo[0] <= b.hi[0]) & (b.lo[0] <= a.hi[0]) & (a.lo[1] <= b.hi[1]) & (b.lo[1] <= a.hi[1]) &
         (a.lo[2] <= b.hi[2]) & (b.lo[2] <= a.hi[2]);
}

/// Calls f(s) for every slot s of `tree` whose box overlaps `q`, in no particular order.
template <class F>
void query(const PairMesh& tree, const Box& q, std::vector<std::uint32_t>& stack, F&& f) {
  if (!tree.has_tree()) return;
  const Node* nodes = tree.nodes;
  stack.clear();
  stack.push_back(0);
  while (!stack.empty()) {
    const Node& node = nodes[stack.back()];
    stack.pop_back();
    if (!overlap(node.box, q)) continue;
    if (node.is_leaf()) {
      for (std::uint32_t s = node.index; s < node.index + node.count; ++s)
        if (overlap(tree.box[s], q)) f(s);
    } else {
      stack.push_back(node.index + 1);
      stack.push_back(node.index);
    }
  }
}

/// All three points strictly on one side of the plane P of triangle t (exact signs).
bool one_side(const Plane& P, const Vec3<double>* t, const Vec3<double>* x) {
  const int s = side(P, t, x[0]);
  return s != 0 && side(P, t, x[1]) == s && side(P, t, x[2]) == s;
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

/// Triangles a = (v, a1, a2) and b = (v, b1, b2) sharing the vertex v, with b1, b2 strictly on
/// opposite sides of a's plane (s1 = orient3d(v, a1, a2, b1) = -orient3d(v, a1, a2, b2) != 0) and
/// a1, a2 strictly on opposite sides of b's plane (t1 = orient3d(v, b1, b2, a1), likewise): whether
/// they share a point other than v, by one more orient3d. The planes then meet in a line L through
/// v, and a meets L in [v, p], p inside the edge a1a2 (b's plane crosses it there), b in [v, q], q
/// inside b1b2; a and b share beyond v exactly when p and q lie on the same side of v on L. The
/// tetrahedron T = (a1, a2, b1, b2) meets L in exactly [p, q] (a point of L beyond p or q has a
/// negative barycentric coordinate), so they share beyond v exactly when v is not in T. v is off
/// the plane of (a1, a2, b1, b2) (else all five points are coplanar and s1 = 0); when T is flat
/// (D = 0) p = q, a common point, and v is not in T either. Else v is in T when its four
/// barycentric signs, orient3d(v, a2, b1, b2) = t2 = -t1, orient3d(a1, v, b1, b2) = -t1,
/// orient3d(a1, a2, v, b2) = s2 = -s1, orient3d(a1, a2, b1, v) = -s1, all have D's sign.
bool crossing_wedges_meet(const Vec3<double>& a1, const Vec3<double>& a2, const Vec3<double>& b1,
                          const Vec3<double>& b2, int s1, int t1) {
  if (s1 != t1) return true;  // the barycentric signs differ: v is not in T
  const int d = certified::orient3d_exact(a1, a2, b1, b2);
  return d != -s1;
}

/// Whether triangles i and j (i != j, both of positive area) of one mesh intersect beyond the
/// vertices they share by index (the header's rule). Exact plane-side signs settle the common
/// cases first (apart, not coplanar); the certified tests decide the rest.
bool self_pair_intersects(const PairMesh& m, std::uint32_t i, std::uint32_t j) {
  const std::uint32_t* a = &m.idx[3 * i];
  const std::uint32_t* b = &m.idx[3 * j];
  Vec3<double> pa[3], pb[3];
  m.corners(i, pa), m.corners(j, pb);
  // Bit 3 y + x: a[x] == b[y] (no branch per comparison: how many indices two candidates share
  // varies from pair to pair). Each triangle here has three distinct indices (else zero area).
  unsigned eq = 0;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 3; ++x) eq |= unsigned(a[x] == b[y]) << (3 * y + x);
  const int shared = std::popcount(eq);
  const Plane qa = plane_of(pa[0], pa[1], pa[2]);
  if (shared == 0) {
    if (one_side(qa, pa, pb) || one_side(plane_of(pb[0], pb[1], pb[2]), pb, pa)) return false;
    return certified::tritri_meets(m.tri(i), m.tri(j));
  }
  if (shared >= 2) {
    // Not coplanar: they meet in the shared edge alone.
    const int b_only = (eq & 7u) == 0 ? 0 : ((eq >> 3) & 7u) == 0 ? 1 : 2;
    if (shared == 2 && side(qa, pa, pb[b_only]) != 0) return false;
    return certified::tritri(m.tri(i), m.tri(j)) == TriTri::coplanar_overlap;
  }
  // One shared vertex: a point in both other than it exists exactly when the edge of one opposite
  // the shared vertex meets the other triangle (the nearer of the two exits of a ray from the
  // shared vertex through such a point lies on an opposite edge and in both triangles).
  const int kb = std::countr_zero(eq) / 3, ka = std::countr_zero(eq) % 3;
  const Vec3<double>& a1 = pa[(ka + 1) % 3];
  const Vec3<double>& a2 = pa[(ka + 2) % 3];
  const Vec3<double>& b1 = pb[(kb + 1) % 3];
  const Vec3<double>& b2 = pb[(kb + 2) % 3];
  // The edge of b opposite v strictly on one side of a's plane puts all of b but v strictly on that
  // side: nothing beyond v in common (two signs settle most pairs of a smooth mesh); likewise a.
  // s_k = orient3d(v, a1, a2, b_k), t_k = orient3d(v, b1, b2, a_k) (pa is a rotation of (v, a1, a2)).
  const int s1 = side(qa, pa, b1);
  const int s2 = s1 != 0 ? side(qa, pa, b2) : 0;
  if (s1 != 0 && s2 == s1) return false;
  const Plane qb = plane_of(pb[0], pb[1], pb[2]);
  const int t1 = side(qb, pb, a1);
  const int t2 = t1 != 0 ? side(qb, pb, a2) : 0;
  if (t1 != 0 && t2 == t1) return false;
  if (s1 != 0 && s2 == -s1 && t1 != 0 && t2 == -t1) return crossing_wedges_meet(a1, a2, b1, b2, s1, t1);
  return segment_meets(b1, b2, pa) || segment_meets(a1, a2, pb);
}

/// Two nodes of one tree whose triangles are paired (a == b: the pairs within one node).
struct NodePair {
  std::uint32_t a, b;
};
/// Levels of the simultaneous descent expanded on the calling thread into tasks (each level about
/// triples their number: a few hundred tasks for the threads).
constexpr int kTaskLevels = 6;

/// A stack of node pairs that grows when full (the descent's hot path: no call per push).
struct PairStack {
  std::vector<NodePair> v = std::vector<NodePair>(256);
  std::size_t n = 0;
  void push(NodePair p) {
    if (n == v.size()) [[unlikely]]
      v.resize(2 * n);
    v[n++] = p;
  }
  [[nodiscard]] bool empty() const { return n == 0; }
  NodePair pop() { return v[--n]; }
};

/// One step of the descent of the tree against itself, on a pair whose boxes overlap (or a node
/// with itself): a node with itself gives its children with themselves and, when their boxes
/// overlap, with each other; two nodes give those children of the larger one whose boxes overlap
/// the other; leaves give their triangles' pairs whose boxes overlap (each unordered pair of
/// distinct triangles once over the whole descent).
template <class Push, class Emit>
void self_step(const PairMesh& m, NodePair t, Push&& push, Emit&& emit) {
  const Node* nodes = m.nodes;
  const Node& A = nodes[t.a];
  if (t.a == t.b) {
    if (A.is_leaf()) {
      // The overlapping pairs as bits (k * kLeaf + l), then emitted: no branch per box test.
      unsigned bits = 0;
      for (std::uint32_t k = 0; k < A.count; ++k)
        for (std::uint32_t l = k + 1; l < A.count; ++l)
          bits |= unsigned(overlap(m.box[A.index + k], m.box[A.index + l])) << (k * kLeaf + l);
      for (; bits != 0; bits &= bits - 1) {
        const auto b = static_cast<std::uint32_t>(std::countr_zero(bits));
        emit(A.index + b / kLeaf, A.index + b % kLeaf);
      }
    } else {
      push(NodePair{A.index, A.index}), push(NodePair{A.index + 1, A.index + 1});
      if (overlap(nodes[A.index].box, nodes[A.index + 1].box)) push(NodePair{A.index, A.index + 1});
    }
    return;
  }
  const Node& B = nodes[t.b];
  if (A.is_leaf() && B.is_leaf()) {
    unsigned bits = 0;
    for (std::uint32_t k = 0; k < A.count; ++k)
      for (std::uint32_t l = 0; l < B.count; ++l)
        bits |= unsigned(overlap(m.box[A.index + k], m.box[B.index + l])) << (k * kLeaf + l);
    for (; bits != 0; bits &= bits - 1) {
      const auto b = static_cast<std::uint32_t>(std::countr_zero(bits));
      emit(A.index + b / kLeaf, B.index + b % kLeaf);
    }
  } else if (B.is_leaf() || (!A.is_leaf() && A.box.half_area() >= B.box.half_area())) {
    if (overlap(nodes[A.index].box, B.box)) push(NodePair{A.index, t.b});
    if (overlap(nodes[A.index + 1].box, B.box)) push(NodePair{A.index + 1, t.b});
  } else {
    if (overlap(A.box, nodes[B.index].box)) push(NodePair{t.a, B.index});
    if (overlap(A.box, nodes[B.index + 1].box)) push(NodePair{t.a, B.index + 1});
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
  for (std::uint32_t s = 0; s < m.size(); ++s)
    if (m.zero_area[s]) pairs.push_back({m.id[s], m.id[s], opt.classes ? TriTri::degenerate : TriTri::invalid});
  // p, q: slots. The pair is decided with the lower input number first (the classes' order).
  const auto test = [&](std::uint32_t p, std::uint32_t q, std::vector<TrianglePair>& out) {
    if (m.zero_area[p] || m.zero_area[q]) return;
    if (m.id[p] > m.id[q]) std::swap(p, q);
    if (!self_pair_intersects(m, p, q)) return;
    out.push_back({m.id[p], m.id[q], opt.classes ? certified::tritri(m.tri(p), m.tri(q)) : TriTri::invalid});
  };
  if (m.has_tree()) {
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
      PairStack stack;
      for (std::size_t t = t0; t < t1; ++t) {
        stack.push(tasks[t]);
        while (!stack.empty()) {
          self_step(m, stack.pop(), [&](NodePair c) { stack.push(c); },
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
      row.push_back({i, mb.id[j], opt.classes ? certified::tritri(ti, mb.tri(j)) : TriTri::invalid});
    });
  });
}

}  // namespace rayproof
