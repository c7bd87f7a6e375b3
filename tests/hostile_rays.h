#pragma once
// Hostile rays near a mesh, shared by the wide-BVH tests (bvh8_test, bvh_quantized_test).
#include <limits>
#include <random>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/ray.h"

namespace rayproof::test {

/// Hostile rays near the mesh: axis-parallel with +-0 components, origins on vertices' coordinate
/// planes (the slab planes of leaf boxes), huge and tiny scalings (the double path), NaN and zero d.
inline std::vector<Ray<double>> hostile_rays(const mesh::Mesh& m, unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<Ray<double>> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < n; ++i) {
    const Vec3<double>& v = m.vertices[rng() % m.vertices.size()];
    Ray<double> r{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
    switch (i % 8) {
      case 0: r.o = {v.x, v.y, -3.0}, r.d = {i % 16 ? 0.0 : -0.0, -0.0, 1.0}; break;  // through a vertex, axis-parallel
      case 1: r.o = {v.x, u(rng), u(rng)}, r.d = {0.0, r.d.y, r.d.z}; break;          // in a vertex's x plane
      case 2: r.o = v * 0x1p70, r.d = (v - r.o) * 0x1p-3; break;                        // huge origin: double path
      case 3: r.d = r.d * 0x1p-70; break;                                               // tiny d: double path
      case 4: r.d = (v - r.o) * 0x1p70; break;                                          // huge d, aimed at a vertex
      case 5: r.d = {nan, 1, 0}; break;                                                 // invalid
      case 6: r.d = {0, 0, 0}; break;                                                   // invalid
      default: r.d = v - r.o; break;                                                    // at a vertex
    }
    out.push_back(r);
  }
  return out;
}

}  // namespace rayproof::test
