// Self-intersections and contact pairs side by side, one thread, as a plain program (for profiling
// rayproof alone with --rayproof-only, and for the sphere sizes of the earlier tables): the rows of
// `rayproof bench intersect` (scene/compare/intersect_bench.h: rayproof beside CGAL PMP Epick and
// Epeck, Open3D and FCL) on bunny00, armadillo, refined_elephant, elephant-with-holes and boeing, the bumpy
// sphere of 81,920 triangles and the same with a shifted copy in one mesh.
//   intersect_bench [MESH_DIR] [--repeat N] [--big] [--rayproof-only]
//   (--big: also the generated 1.31M-triangle sphere)
#include <fmt/core.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "scene/compare/intersect_bench.h"
#include "scene/watertight.h"

namespace cmp = rayproof::scene::compare;

namespace {

void print(const cmp::IntersectRow& row) {
  fmt::print("{:<34} {:>9}{} triangles  rayproof {:>7} pairs {:>9.4f} s\n", row.name, row.triangles,
             row.two ? fmt::format(" x {}", row.triangles2) : "", row.pairs, row.seconds);
  for (const auto& p : row.peers) fmt::print("    {}\n", cmp::peer_sentence(row, p));
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = RAYPROOF_BENCH_MESH_DIR;
  cmp::IntersectBenchOptions opt;
  bool big = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) opt.repeat = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--big") == 0) big = true;
    else if (std::strcmp(argv[i], "--rayproof-only") == 0) opt.peers = false;
    else dir = argv[i];
  }
  fmt::print("one thread, thread CPU time, least of {} runs\n", opt.repeat);
  std::vector<cmp::NamedMesh> meshes;
  for (const char* f : {"bunny00.off", "armadillo.off", "refined_elephant.off", "elephant-with-holes.off", "boeing.off"}) {
    const auto p = std::filesystem::path(dir) / f;
    if (std::filesystem::exists(p)) meshes.push_back({f, rayproof::mesh::read_mesh(p.string())});
    else fmt::print("{}: not found, skipped\n", p.string());
  }
  const rayproof::mesh::Mesh sphere = rayproof::scene::bumpy_sphere(80000);
  meshes.push_back({"bumpy sphere", sphere});
  meshes.push_back({"bumpy sphere + shifted copy", cmp::joined(sphere, cmp::moved(sphere, {0.6, 0.2, 0.1}))});
  if (big) meshes.push_back({"bumpy sphere 1.31M", rayproof::scene::bumpy_sphere(std::size_t(1) << 20)});
  for (const auto& m : meshes) print(cmp::self_intersect_row(m.name, m.mesh, opt));
  for (const auto& m : meshes)
    if (m.mesh.triangles.size() < 100000) print(cmp::contact_row(m.name + " vs shifted copy", m.mesh, cmp::shifted_copy(m.mesh), opt));
  return 0;
}
