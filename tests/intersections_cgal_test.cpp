// self_intersections (rayproof/scene/intersections.h) equal to CGAL Polygon_mesh_processing's
// self_intersections (Epick: exact predicates) on generated meshes: a closed bumpy sphere, two
// overlapping copies of it, a copy moved by one ulp, a folded sheet, cubes touching at a face, a
// mesh with zero-area triangles; and bunny00 when the build has CGAL's data.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "intersect_meshes.h"
#include "mesh/mesh.h"
#include "scene/watertight.h"

namespace {

using namespace rayproof;
using namespace rayproof::testing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;

/// CGAL's pairs, each as (lower, higher) face number (faces numbered in insertion order), sorted.
std::vector<TrianglePair> cgal_self(const mesh::Mesh& m) {
  SM sm;
  for (const auto& v : m.vertices) sm.add_vertex(K::Point_3(v.x, v.y, v.z));
  for (const auto& t : m.triangles) {
    const auto f = sm.add_face(SM::Vertex_index(t[0]), SM::Vertex_index(t[1]), SM::Vertex_index(t[2]));
    EXPECT_NE(f, SM::null_face()) << "not a manifold mesh";
  }
  std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
  std::vector<TrianglePair> out;
  for (auto [f, g] : pairs) {
    const auto a = std::uint32_t(f), b = std::uint32_t(g);
    out.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SelfIntersectionsCgal, GeneratedMeshes) {
  std::vector<std::pair<const char*, mesh::Mesh>> cases;
  cases.push_back({"bumpy sphere", scene::bumpy_sphere(1200)});
  mesh::Mesh two = scene::bumpy_sphere(1200), moved = two;
  for (auto& v : moved.vertices) v = v + Vec3<double>{0.7, 0.1, 0.05};
  append(two, moved);
  cases.push_back({"two overlapping spheres", two});
  mesh::Mesh ulp = scene::bumpy_sphere(300), copy = ulp;
  for (auto& v : copy.vertices) v.x = std::nextafter(v.x, 10.0);
  append(ulp, copy);
  cases.push_back({"a copy moved by one ulp", ulp});
  cases.push_back({"folded sheet", folded_sheet(8, 5)});
  mesh::Mesh cubes = box({0, 0, 0}, {2, 2, 2});
  append(cubes, box({2, 0, 0}, {2, 2, 2}));
  append(cubes, box({1, 1, 1}, {2, 2, 2}));
  cases.push_back({"cubes touching and overlapping", cubes});
  mesh::Mesh flat = folded_sheet(4, 10);  // not folded: a flat sheet
  flat.vertices[6] = {0.5, 0, 0};          // vertex (1, 1) moved onto the edge (0, 0)-(1, 0): triangle 0 collinear
  cases.push_back({"zero-area triangles", flat});
  for (const auto& [name, m] : cases) {
    const auto want = cgal_self(m);
    EXPECT_EQ(self_of(m), want) << name;
    EXPECT_EQ(want.empty(), std::string(name) == "bumpy sphere") << name << ": " << want.size() << " pairs";
  }
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(SelfIntersectionsCgal, Bunny00) {
  const std::filesystem::path p = std::filesystem::path(RAYPROOF_CGAL_MESHES) / "bunny00.off";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << p << " not found";
  const mesh::Mesh m = mesh::read_mesh(p.string());
  EXPECT_EQ(self_of(m), cgal_self(m));
}
#endif

}  // namespace
