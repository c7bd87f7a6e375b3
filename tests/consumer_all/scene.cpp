// rayproof::scene: MeshCaster on a closed octahedron given as the user's own arrays (float vertices
// with a 16-byte stride, packed indices). Rays from an interior point toward every vertex and edge
// midpoint must hit it (a miss is a leak) with cast::Robust and cast::Certified, one at a time and
// in a batch over TBB threads.
#include <rayproof/scene/mesh_caster.h>

#include <cstdint>
#include <cstdio>
#include <vector>

#include "checks.h"

namespace {

template <class Method>
int leaks(const char* name, const rayproof::VertexArray& vertices, const rayproof::IndexArray& indices,
          const std::vector<rayproof::Ray<double>>& rays) {
  const rayproof::MeshCaster<Method> caster(vertices, indices);
  std::vector<rayproof::MeshHit> batch(rays.size());
  caster.closest(rays, {}, batch, 2);
  int n = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto one = caster.closest(rays[i]);
    if (!one.hit() || !batch[i].hit() || one.triangle != batch[i].triangle || one.t != batch[i].t) {
      std::printf("scene: %s: ray %zu: one at a time triangle %u t %g, batch triangle %u t %g\n", name, i,
                  one.triangle, one.t, batch[i].triangle, batch[i].t);
      ++n;
    }
  }
  std::printf("scene: %s: %zu rays cast, %d leaks or disagreements\n", name, rays.size(), n);
  return n;
}

}  // namespace

int check_scene() {
  using namespace rayproof;
  // x y z and one unused float per vertex: a 16-byte stride.
  const std::vector<float> vertices = {1, 0, 0, 9, -1, 0, 0, 9, 0, 1, 0, 9, 0, -1, 0, 9, 0, 0, 1, 9, 0, 0, -1, 9};
  const std::vector<std::uint32_t> indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  const VertexArray va(vertices.data(), 6, 4 * sizeof(float));
  const IndexArray ia{indices.data(), 8};
  const auto vertex = [&](std::uint32_t i) { return Vec3<double>{vertices[4 * i], vertices[4 * i + 1], vertices[4 * i + 2]}; };
  const Vec3<double> origin{0.125, -0.0625, 0.03125};
  std::vector<Ray<double>> rays;
  for (std::uint32_t v = 0; v < 6; ++v) rays.push_back({origin, vertex(v) - origin});
  for (std::size_t t = 0; t < indices.size(); t += 3)
    for (int k = 0; k < 3; ++k)
      rays.push_back({origin, (vertex(indices[t + k]) + vertex(indices[t + (k + 1) % 3])) * 0.5 - origin});
  return leaks<cast::Robust>("robust", va, ia, rays) + leaks<cast::Certified>("certified", va, ia, rays);
}
