// rayproof::scene: a closed octahedron from the user's arrays; rays from an interior point toward
// every vertex and edge midpoint must hit it (a miss is a leak) with the watertight kernel.
#include <scene/accel.h>

#include <cstdio>

#include "checks.h"

int check_scene() {
  using namespace rayproof;
  scene::Scene s;
  s.mesh.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  s.mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const scene::Accel accel(s);
  MethodRegistry registry;
  register_robust_methods(registry);
  const auto method = scene::find_scene_method("robust", registry);
  const Vec3<double> origin{0.125, -0.0625, 0.03125};
  std::vector<Vec3<double>> targets(s.mesh.vertices.begin(), s.mesh.vertices.end());
  for (const auto& t : s.mesh.triangles)
    for (int k = 0; k < 3; ++k) targets.push_back((s.mesh.vertices[t[k]] + s.mesh.vertices[t[(k + 1) % 3]]) * 0.5);
  int leaks = 0;
  for (const auto& p : targets) {
    const auto hit = accel.closest(Ray<double>{origin, p - origin}, method);
    if (hit.prim == scene::PrimHit::kNoPrim) {
      std::printf("scene: leak toward (%g, %g, %g)\n", p.x, p.y, p.z);
      ++leaks;
    }
  }
  std::printf("scene: %zu rays cast, %d leaks\n", targets.size(), leaks);
  return leaks;
}
