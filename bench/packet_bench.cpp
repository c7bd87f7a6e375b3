/// Packets (rayproof/bvh_packet.h): ns per ray of Accel::closest_packets /
/// any_packets against closest_batch / any_batch (single rays) on the same accel and the same rays,
/// primary rays of the default camera in 4x2 tiles, one thread. The two paths run interleaved,
/// round after round; each reports its fastest round and the ratio single / packet, so ratios
/// taken in one run are comparable on a busy machine.
/// Run: packet_bench [mesh.off] [rounds] [width] [height] [methods]  (default: a generated closed
/// mesh of ~80k triangles, 7 rounds, 640x480, "float,robust,certified").
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "registry/registry.h"
#include "rayproof/bvh_packet.h"
#include "scene/accel.h"
#include "scene/watertight.h"

using namespace rayproof;
using namespace rayproof::scene;

namespace {
double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
}  // namespace

int main(int argc, char** argv) {
  const std::string mesh = argc > 1 ? argv[1] : "";
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 7;
  const int width = argc > 3 ? std::max(1, std::atoi(argv[3])) : 640, height = argc > 4 ? std::max(1, std::atoi(argv[4])) : 480;
  std::string methods = argc > 5 ? argv[5] : "float,robust,certified";
  Scene s;
  try {
    if (mesh.empty()) add_mesh(s, bumpy_sphere(80000));
    else s = load_scene(mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "packet_bench: %s\n", e.what());
    return 2;
  }
  const Accel a(s, {BvhBuilder::sah, 4});
  std::printf("%s: %zu triangles, path %s, %dx%d primary rays in 4x2 tiles, %d rounds (fastest kept)\n",
              mesh.empty() ? "generated" : mesh.c_str(), s.mesh.triangles.size(), to_string(a.simd()), width, height, rounds);
  const Camera cam = default_camera(s, width, height);
  std::vector<Ray<double>> rays;
  for (std::uint32_t p : packet_tile_order(width, height)) rays.push_back(cam.generate(int(p % unsigned(width)), int(p / unsigned(width))));
  std::printf("%-10s %-8s %12s %12s %8s %6s %6s\n", "method", "query", "single ns", "packet ns", "ratio", "same", "hit %");
  for (std::size_t p = 0; p <= methods.size();) {
    const std::size_t q = std::min(methods.find(',', p), methods.size());
    const std::string name = methods.substr(p, q - p);
    p = q + 1;
    if (name.empty()) continue;
    const SceneMethod m = find_scene_method(name, registry::all_methods());
    for (const bool closest : {true, false}) {
      std::vector<PrimHit> c1(rays.size()), c2(rays.size());
      std::vector<std::uint8_t> y1(rays.size()), y2(rays.size());
      double best[2] = {1e30, 1e30};
      for (int r = 0; r < rounds; ++r) {
        double t = now();
        if (closest) a.closest_batch(rays, c1, m, 1);
        else a.any_batch(rays, y1, m, 1);
        best[0] = std::min(best[0], now() - t);
        t = now();
        if (closest) a.closest_packets(rays, {}, c2, m, 1);
        else a.any_packets(rays, {}, y2, m, 1);
        best[1] = std::min(best[1], now() - t);
      }
      std::size_t same = 0, hit = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        same += closest ? c1[i] == c2[i] : y1[i] == y2[i];
        hit += closest ? c1[i].prim != PrimHit::kNoPrim : y1[i] != 0;
      }
      const double n = double(rays.size());
      std::printf("%-10s %-8s %12.1f %12.1f %8.3f %6s %6.1f\n", name.c_str(), closest ? "closest" : "any", 1e9 * best[0] / n,
                  1e9 * best[1] / n, best[0] / best[1], same == rays.size() ? "yes" : "NO", 100.0 * double(hit) / n);
    }
  }
  return 0;
}
