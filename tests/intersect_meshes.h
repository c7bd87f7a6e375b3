// Small meshes for the self-intersection tests: cubes, a welded box, a folded sheet, a bumpy sphere
// with a shifted copy, a random soup; and a brute force over all pairs with the certified tests.
#pragma once

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/certified/tritri.h"
#include "rayproof/scene/intersections.h"

namespace rayproof::testing {

inline std::vector<TrianglePair> self_of(const mesh::Mesh& m, IntersectOptions opt = {}) {
  return self_intersections(VertexArray(&m.vertices[0].x, m.vertices.size()),
                            IndexArray{m.triangles.empty() ? nullptr : m.triangles.front().data(), m.triangles.size()},
                            opt);
}

inline MeshArrays arrays_of(const mesh::Mesh& m) {
  return {VertexArray(&m.vertices[0].x, m.vertices.size()),
          IndexArray{m.triangles.empty() ? nullptr : m.triangles.front().data(), m.triangles.size()}};
}

/// Appends b to a (b's indices shifted: no index shared).
inline void append(mesh::Mesh& a, const mesh::Mesh& b) {
  const auto off = static_cast<std::uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
}

/// The box [lo, lo + size], outward, 12 triangles.
inline mesh::Mesh box(Vec3<double> lo, Vec3<double> size) {
  mesh::Mesh m;
  for (int k = 0; k < 8; ++k)
    m.vertices.push_back({lo.x + (k & 1 ? size.x : 0), lo.y + (k & 2 ? size.y : 0), lo.z + (k & 4 ? size.z : 0)});
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

/// A sheet of n x n squares in z = 0 over [0, n]^2, folded along x = k onto itself (x > k mapped to
/// 2k - x): the triangles on either side of the fold line lie on one another, the ones across it
/// share an edge and overlap.
inline mesh::Mesh folded_sheet(int n, int k) {
  mesh::Mesh m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.vertices.push_back({double(x > k ? 2 * k - x : x), double(y), 0.0});
  const auto at = [n](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      m.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      m.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
  return m;
}

/// `n` triangles with small integer coordinates in [0, 6]^3 and vertex indices drawn from a pool of
/// `pool` points, so that shared indices, shared coordinates, coplanar contacts and zero-area
/// triangles all occur.
inline mesh::Mesh lattice_soup(int n, int pool, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> c(0, 6), v(0, pool - 1);
  mesh::Mesh m;
  for (int i = 0; i < pool; ++i) m.vertices.push_back({double(c(rng)), double(c(rng)), double(c(rng))});
  for (int i = 0; i < n; ++i) {
    std::uint32_t a = v(rng), b = v(rng), d = v(rng);
    while (b == a) b = v(rng);
    while (d == a || d == b) d = v(rng);
    m.triangles.push_back({a, b, d});
  }
  return m;
}

/// The definition of self_intersections, over every pair (no tree), written from the header's rule.
inline std::vector<TrianglePair> brute_self(const mesh::Mesh& m) {
  std::vector<TrianglePair> out;
  const auto tri = [&](std::size_t t) {
    return Triangle<double>{m.vertices[m.triangles[t][0]], m.vertices[m.triangles[t][1]], m.vertices[m.triangles[t][2]]};
  };
  const std::size_t n = m.triangles.size();
  std::vector<bool> degenerate(n);
  for (std::size_t i = 0; i < n; ++i) degenerate[i] = certified::tritri(tri(i), tri(i)) == TriTri::degenerate;
  for (std::size_t i = 0; i < n; ++i) {
    if (degenerate[i]) {
      out.push_back({std::uint32_t(i), std::uint32_t(i)});
      continue;
    }
    for (std::size_t j = i + 1; j < n; ++j) {
      if (degenerate[j]) continue;
      std::vector<std::uint32_t> shared;
      for (auto x : m.triangles[i])
        for (auto y : m.triangles[j])
          if (x == y) shared.push_back(x);
      bool hit = false;
      if (shared.empty()) {
        hit = meets(certified::tritri(tri(i), tri(j)));
      } else if (shared.size() >= 2) {
        hit = certified::tritri(tri(i), tri(j)) == TriTri::coplanar_overlap;
      } else {
        // Some point of both other than the shared vertex: some opposite edge meets the other.
        for (int side = 0; side < 2 && !hit; ++side) {
          const auto& t = m.triangles[side ? j : i];
          std::vector<Vec3<double>> rest;
          for (auto x : t)
            if (x != shared[0]) rest.push_back(m.vertices[x]);
          hit = certified::tritri_meets(Triangle<double>{rest[0], rest[1], rest[1]}, tri(side ? i : j));
        }
      }
      if (hit) out.push_back({std::uint32_t(i), std::uint32_t(j)});
    }
  }
  return out;
}

inline std::vector<TrianglePair> brute_pairs(const mesh::Mesh& a, const mesh::Mesh& b) {
  std::vector<TrianglePair> out;
  for (std::size_t i = 0; i < a.triangles.size(); ++i)
    for (std::size_t j = 0; j < b.triangles.size(); ++j) {
      const auto& s = a.triangles[i];
      const auto& t = b.triangles[j];
      if (certified::tritri_meets({a.vertices[s[0]], a.vertices[s[1]], a.vertices[s[2]]},
                                  {b.vertices[t[0]], b.vertices[t[1]], b.vertices[t[2]]}))
        out.push_back({std::uint32_t(i), std::uint32_t(j)});
    }
  return out;
}

}  // namespace rayproof::testing
