// rayproof cast MESH RAYS --query crossings: load the mesh as an ExactMesh (any mesh: open ones
// and soups too), read the rays, print each ray's crossings (and touches).
#include "cli/mesh_input.h"
#include "cli/cast_crossings.h"

#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "cli/input.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "scene/ray_file.h"

namespace rayproof::cli {

int run_cast_crossings(const CastCrossingsArgs& a) {
  const char* me = "rayproof cast";
  auto loaded = read_closed_mesh(me, a.mesh);
  if (!loaded) return 2;
  const mesh::Mesh& m = loaded->mesh;
  const std::unique_ptr<ExactMesh>& cm = loaded->closed;
  if (a.verbose) fmt::print(stderr, "{}: {}: {} triangles, {}\n", me, a.mesh, m.triangles.size(), cm->closed() ? "closed" : "not closed");
  if (!(a.tmin <= a.tmax)) {
    fmt::print(stderr, "{}: --tmin {} is not <= --tmax {}\n", me, a.tmin, a.tmax);
    return 2;
  }
  Input in = open_input(a.rays);
  if (!in.stream) {
    fmt::print(stderr, "{}: {}\n", me, in.error);
    return 2;
  }
  std::vector<Ray<double>> rays;
  std::vector<std::string> errors;
  try {
    for (auto& r : scene::read_rays(*in.stream, a.rays)) rays.push_back(r.ray), errors.push_back(std::move(r.error));
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: {}\n", me, e.what());
    return 2;
  }
  if (rays.empty()) {
    fmt::print(stderr, "{}: {}: no rays (expected lines 'ox oy oz dx dy dz')\n", me, a.rays);
    return 2;
  }
  std::vector<RayCrossings> out(rays.size());
  cm->ray_crossings(rays, out, {a.tmin, a.tmax}, a.threads);
  std::string text;
  int bad = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!errors[i].empty()) {
      fmt::print(stderr, "{}: {}\n", me, errors[i]);
      text += "error\n";
      ++bad;
      continue;
    }
    const RayCrossings& r = out[i];
    if (!r.valid) {
      text += "invalid\n";
      continue;
    }
    text += std::to_string(r.crossings.size());
    for (const Crossing& c : r.crossings) text += fmt::format(" {}:{}", io::format_double(c.t), to_string(c.direction));
    if (a.touches) {
      text += fmt::format(" | {}", r.touches.size());
      for (const Touch& t : r.touches) {
        if (t.contact == Contact::coplanar)
          text += fmt::format(" {}..{}:coplanar", io::format_double(t.t), io::format_double(t.t2));
        else
          text += fmt::format(" {}:{}", io::format_double(t.t), to_string(t.contact));
      }
    }
    text += '\n';
    if (text.size() > (1 << 16)) std::fwrite(text.data(), 1, text.size(), stdout), text.clear();
  }
  std::fwrite(text.data(), 1, text.size(), stdout);
  if (bad) fmt::print(stderr, "{}: {} line(s) could not be read\n", me, bad);
  return bad ? 1 : 0;
}

}  // namespace rayproof::cli
