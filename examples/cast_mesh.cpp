// Casting rays on your own mesh arrays with rayproof::MeshCaster (include/rayproof/scene/mesh_caster.h).
// Links rayproof::scene only; MeshCaster<rayproof::cast::Certified> also needs rayproof::scene_certified.
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "rayproof/scene/mesh_caster.h"

int main() {
  // A unit square in the z = 0 plane: four float vertices, two triangles (your arrays, any stride).
  const std::vector<float> vertices = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const std::vector<std::uint32_t> indices = {0, 1, 2, 0, 2, 3};

  const rayproof::MeshCaster<rayproof::cast::Robust> caster(rayproof::VertexArray(vertices.data(), 4),
                                                            rayproof::IndexArray{indices.data(), 2});
  const rayproof::Ray<double> ray{{1, 1, 2}, {-0.25, -0.25, -1}};  // hits the shared edge at its midpoint
  const rayproof::MeshHit hit = caster.closest(ray);
  if (!hit.hit()) return std::puts("miss"), 1;
  std::printf("triangle %u, t = %g, %s, barycentrics %g %g\n", hit.triangle, hit.t,
              std::string(rayproof::to_string(hit.contact)).c_str(), hit.b1, hit.b2);
  return 0;
}
