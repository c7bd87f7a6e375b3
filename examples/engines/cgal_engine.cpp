// CGAL as the judged function of `rayproof check` (docs/check.md), in CGAL's Epick kernel (double
// coordinates, exact predicates, double constructions), written as a CGAL user writes it. One
// program, so that CGAL's headers are compiled once:
//
//   cgal_engine distance: an AABB_tree of the triangles with accelerate_distance_queries(), and per
//     point sqrt(squared_distance(p, closest_point(p))) (`check --distance`);
//   cgal_engine closest: the same tree's closest_point_and_primitive(p): the distance to that
//     point, the point and its triangle's index (`d x y z triangle`, `check --distance`);
//   cgal_engine contains: the triangles as a Surface_mesh (through CGAL's polygon soup functions,
//     which orient the soup where it is not already a mesh) and Side_of_triangle_mesh per point:
//     ON_BOUNDED_SIDE 1, ON_BOUNDARY 2, ON_UNBOUNDED_SIDE 0 (`check --contains`). CGAL documents it
//     for closed meshes; on an open one it answers all the same.
//
//   rayproof check --distance 'cgal=build/examples/cgal_engine distance' --mesh mesh.off
//   rayproof check --distance 'cgal=build/examples/cgal_engine closest' --mesh mesh.off
//   rayproof check --contains 'cgal=build/examples/cgal_engine contains' --mesh mesh.off
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <string_view>

#include "line_protocol.h"

namespace {

using K = CGAL::Epick;
using Points = std::vector<std::array<double, 3>>;

K::Point_3 point(const std::array<double, 3>& p) { return {p[0], p[1], p[2]}; }

/// `closest`: with the closest point and its triangle, else the distance alone.
void distance(bool closest) {
  using Triangle = K::Triangle_3;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>>>;
  const engine_example::Mesh mesh = engine_example::read_mesh("rayproof-distance");
  std::vector<Triangle> triangles;
  for (const auto& t : mesh.triangles)
    triangles.emplace_back(point(mesh.vertices.at(t[0])), point(mesh.vertices.at(t[1])), point(mesh.vertices.at(t[2])));
  Tree tree(triangles.cbegin(), triangles.cend());
  tree.accelerate_distance_queries();
  engine_example::serve_batches([&](const Points& points) {
    std::vector<std::string> answers;
    for (const auto& p : points) {
      const K::Point_3 q = point(p);
      if (!closest) {
        answers.push_back(fmt::format("{}", std::sqrt(CGAL::squared_distance(q, tree.closest_point(q)))));
        continue;
      }
      const auto [x, id] = tree.closest_point_and_primitive(q);
      answers.push_back(fmt::format("{} {} {} {} {}", std::sqrt(CGAL::squared_distance(q, x)), x.x(), x.y(), x.z(),
                                    id - triangles.cbegin()));
    }
    return answers;
  });
}

void contains() {
  namespace PMP = CGAL::Polygon_mesh_processing;
  using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
  const engine_example::Mesh mesh = engine_example::read_mesh("rayproof-contains");
  std::vector<K::Point_3> vertices;
  for (const auto& v : mesh.vertices) vertices.push_back(point(v));
  std::vector<std::vector<std::size_t>> polygons;
  for (const auto& t : mesh.triangles) polygons.push_back({t[0], t[1], t[2]});
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) PMP::orient_polygon_soup(vertices, polygons);
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(vertices, polygons, sm);
  const CGAL::Side_of_triangle_mesh<SurfaceMesh, K> side(sm);
  engine_example::serve_batches([&](const Points& points) {
    std::vector<std::string> answers;
    for (const auto& p : points) {
      const CGAL::Bounded_side s = side(point(p));
      answers.emplace_back(s == CGAL::ON_BOUNDED_SIDE ? "1" : s == CGAL::ON_BOUNDARY ? "2" : "0");
    }
    return answers;
  });
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view what = argc == 2 ? argv[1] : "";
  if (what == "distance" || what == "closest") distance(what == "closest");
  else if (what == "contains") contains();
  else engine_example::fail("usage: cgal_engine distance|closest|contains (then the line protocol on stdin)");
}
