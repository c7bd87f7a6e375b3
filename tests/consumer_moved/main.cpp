// A downstream program written to the docs before the public headers moved into folders by library:
// it includes the six old paths (rayproof/certified.h, exact.h, check.h, gtest.h, contains.h,
// mesh_caster.h), which must still build, with one deprecation message each, and work. It also names
// the mesh object by its earlier name, ClosedMesh (now ExactMesh), which must warn and work too.
#include <rayproof/certified.h>
#include <rayproof/check.h>
#include <rayproof/contains.h>
#include <rayproof/exact.h>
#include <rayproof/gtest.h>
#include <rayproof/mesh_caster.h>

#include <cstdint>
#include <cstdio>
#include <vector>

int main() {
  using namespace rayproof;
  using V = Vec3<double>;
  int failures = 0;
  // certified.h and exact.h: an edge hit, exactly on the edge p0-p1 (t = 2).
  const Ray<double> ray{V{0.5, 0, -2}, V{0, 0, 1}};
  const Triangle<double> tri{V{0, 0, 0}, V{1, 0, 0}, V{0, 1, 0}};
  const auto c = certified::intersect(ray, tri);
  const auto e = exact::intersect(ray, tri);
  if (c.contact != Contact::edge || e.contact != Contact::edge || c.t != 2 || e.t != 2) {
    std::printf("moved headers: certified %s %g, exact %s %g, want edge 2\n", to_string(c.contact).data(), c.t,
                to_string(e.contact).data(), e.t);
    ++failures;
  }
  // gtest.h: the helper itself, without a test runner.
  const auto same = [](const Ray<double>& r, const Triangle<double>& t) { return certified::intersect(r, t); };
  if (!gtest::matches_exact(same, ray, tri, 0)) {
    std::printf("moved headers: matches_exact refused certified::intersect\n");
    ++failures;
  }
  // check.h: the checker over the triangle families.
  verify::KernelCheckOptions opt;
  opt.count = 4;
  opt.exact_class = true;
  const auto k = verify::check(verify::TriangleKernel<double>(same), opt);
  if (k.cases() == 0 || !k.promises_kept()) {
    std::printf("moved headers: check ran %zu cases, promises %s\n", k.cases(), k.promises_kept() ? "kept" : "broken");
    ++failures;
  }
  // mesh_caster.h and contains.h: a closed tetrahedron, a ray from inside and a point inside.
  const std::vector<double> vertices = {0, 0, 0, 4, 0, 0, 0, 4, 0, 0, 0, 4};
  const std::vector<std::uint32_t> indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  const VertexArray va(vertices.data(), 4, 3 * sizeof(double));
  const IndexArray ia{indices.data(), 4};
  const MeshCaster<cast::Certified> caster(va, ia);
  const auto hit = caster.closest(Ray<double>{V{0.5, 0.5, 0.5}, V{-1, 0, 0}});
  const ClosedMesh mesh(va, ia);
  if (!hit.hit() || hit.t != 0.5 || mesh.contains(V{0.5, 0.5, 0.5}) != Side::inside) {
    std::printf("moved headers: cast hit %d t %g, containment wrong or hit missing\n", hit.hit() ? 1 : 0, hit.t);
    ++failures;
  }
  std::printf("moved headers: %d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
