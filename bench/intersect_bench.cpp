// Self-intersections side by side, one thread: rayproof::self_intersections (BVH candidates,
// certified triangle/triangle decisions) against CGAL Polygon_mesh_processing::self_intersections
// (Epick, Sequential_tag) on bunny00, refined_elephant, elephant-with-holes and boeing (CGAL data meshes
// that self-intersect) and generated meshes with self-intersections;
// and, when the build found FCL (libfcl-dev), rayproof::intersecting_pairs against FCL's mesh-mesh
// collision (OBBRSS trees, every contact) on two meshes. Prints the pairs each finds, the pairs that
// differ and the time ratio. A plain program (bench only: PMP is not in the tool's libraries).
//   intersect_bench [MESH_DIR] [--repeat N] [--big]   (--big: also the generated 1.31M-triangle sphere)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/core.h>

#ifdef RAYPROOF_HAVE_FCL
#include <fcl/fcl.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/intersections.h"
#include "scene/watertight.h"

namespace {

using namespace rayproof;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
using Pairs = std::vector<TrianglePair>;
bool rayproof_only = false;  ///< --rayproof-only: no peers (for profiling)

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The least time of `repeat` runs of f (its last result kept in `out`).
template <class F, class R>
double best_of(int repeat, F&& f, R& out) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    out = f();
    best = std::min(best, seconds_since(t0));
  }
  return best;
}

MeshArrays arrays(const mesh::Mesh& m) {
  return {VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()}};
}

void append(mesh::Mesh& a, const mesh::Mesh& b) {
  const auto off = static_cast<std::uint32_t>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
}

mesh::Mesh moved(mesh::Mesh m, Vec3<double> d) {
  for (auto& v : m.vertices) v = v + d;
  return m;
}

/// Pairs of `a` not in `b` (both sorted).
std::size_t missing_from(const Pairs& a, const Pairs& b) {
  std::size_t n = 0;
  for (const auto& p : a) n += !std::binary_search(b.begin(), b.end(), p);
  return n;
}

/// CGAL's pairs as sorted (lower, higher) face numbers; false when the mesh is not a manifold
/// Surface_mesh (add_face refused a face).
bool cgal_pairs(const SM& sm, Pairs& out) {
  std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(sm, std::back_inserter(pairs));
  out.clear();
  for (auto [f, g] : pairs) out.push_back({std::min(std::uint32_t(f), std::uint32_t(g)), std::max(std::uint32_t(f), std::uint32_t(g))});
  std::sort(out.begin(), out.end());
  return true;
}

void self_row(const std::string& name, const mesh::Mesh& m, int repeat) {
  SM sm;
  for (const auto& v : m.vertices) sm.add_vertex(K::Point_3(v.x, v.y, v.z));
  std::size_t refused = 0;
  for (const auto& t : m.triangles)
    refused += sm.add_face(SM::Vertex_index(t[0]), SM::Vertex_index(t[1]), SM::Vertex_index(t[2])) == SM::null_face();
  IntersectOptions one;
  one.threads = 1;
  Pairs ours, theirs;
  const double t_ours = best_of(repeat, [&] { return self_intersections(arrays(m).vertices, arrays(m).indices, one); }, ours);
  fmt::print("{:<28} {:>9} triangles  rayproof {:>7} pairs {:>9.4f} s", name, m.triangles.size(), ours.size(), t_ours);
  if (rayproof_only) {
    fmt::print("\n");
    return;
  }
  if (refused) {
    fmt::print("  CGAL: {} faces not manifold, skipped\n", refused);
    return;
  }
  const double t_cgal = best_of(std::max(1, repeat / 2), [&] { Pairs p; cgal_pairs(sm, p); return p; }, theirs);
  fmt::print("  CGAL PMP {:>7} pairs {:>9.4f} s  differ: {} only rayproof, {} only CGAL  CGAL/rayproof {:.2f}x\n",
             theirs.size(), t_cgal, missing_from(ours, theirs), missing_from(theirs, ours), t_cgal / t_ours);
}

#ifdef RAYPROOF_HAVE_FCL
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const mesh::Mesh& m) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v;
  std::vector<fcl::Triangle> t;
  for (const auto& p : m.vertices) v.emplace_back(p.x, p.y, p.z);
  for (const auto& f : m.triangles) t.emplace_back(f[0], f[1], f[2]);
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  return model;
}

Pairs fcl_pairs(const mesh::Mesh& a, const mesh::Mesh& b) {
  fcl::CollisionObjectd oa(fcl_model(a)), ob(fcl_model(b));
  fcl::CollisionRequestd req(std::size_t(1) << 30, false);
  fcl::CollisionResultd res;
  fcl::collide(&oa, &ob, req, res);
  std::vector<fcl::Contactd> contacts;
  res.getContacts(contacts);
  Pairs out;
  for (const auto& c : contacts) out.push_back({std::uint32_t(c.b1), std::uint32_t(c.b2)});
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}
#endif

void pair_row(const std::string& name, const mesh::Mesh& a, const mesh::Mesh& b, int repeat) {
  IntersectOptions one;
  one.threads = 1;
  Pairs ours;
  const double t_ours = best_of(repeat, [&] { return intersecting_pairs(arrays(a), arrays(b), one); }, ours);
  fmt::print("{:<28} {:>9} x {:<9} rayproof {:>7} pairs {:>9.4f} s", name, a.triangles.size(), b.triangles.size(),
             ours.size(), t_ours);
#ifdef RAYPROOF_HAVE_FCL
  if (rayproof_only) {
    fmt::print("\n");
    return;
  }
  Pairs theirs;
  const double t_fcl = best_of(repeat, [&] { return fcl_pairs(a, b); }, theirs);
  fmt::print("  FCL {:>7} pairs {:>9.4f} s  differ: {} only rayproof, {} only FCL  FCL/rayproof {:.2f}x\n", theirs.size(),
             t_fcl, missing_from(ours, theirs), missing_from(theirs, ours), t_fcl / t_ours);
#else
  fmt::print("  FCL: not built (libfcl-dev not found)\n");
#endif
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = RAYPROOF_BENCH_MESH_DIR;
  int repeat = 3;
  bool big = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--big") == 0) big = true;
    else if (std::strcmp(argv[i], "--rayproof-only") == 0) rayproof_only = true;
    else dir = argv[i];
  }
  fmt::print("one thread; best of {} (CGAL best of {})\n", repeat, std::max(1, repeat / 2));
  std::vector<std::pair<std::string, mesh::Mesh>> meshes;
  for (const char* f : {"bunny00.off", "refined_elephant.off", "elephant-with-holes.off", "boeing.off"}) {
    const auto p = std::filesystem::path(dir) / f;
    if (std::filesystem::exists(p)) meshes.push_back({f, mesh::read_mesh(p.string())});
    else fmt::print("{}: not found, skipped\n", p.string());
  }
  const mesh::Mesh sphere = scene::bumpy_sphere(80000);
  meshes.push_back({"bumpy sphere", sphere});
  mesh::Mesh two = sphere;
  append(two, moved(sphere, {0.6, 0.2, 0.1}));
  meshes.push_back({"bumpy sphere + shifted copy", two});
  if (big) meshes.push_back({"bumpy sphere 1.31M", scene::bumpy_sphere(std::size_t(1) << 20)});
  for (const auto& [name, m] : meshes) self_row(name, m, repeat);
  for (const auto& [name, m] : meshes) {
    if (name == "bumpy sphere + shifted copy" || name == "bumpy sphere 1.31M") continue;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const auto& v : m.vertices)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
    const Vec3<double> d{0.3 * (hi[0] - lo[0]), 0.1 * (hi[1] - lo[1]), 0.05 * (hi[2] - lo[2])};
    pair_row(name + " vs shifted copy", m, moved(m, d), repeat);
  }
  return 0;
}
