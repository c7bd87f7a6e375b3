// rayproof::certified: certified::intersect on a contact of every kind that only exact signs decide
// (an edge, a tangent, a graze, a rim), each built so that its t is an exact double.
#include <rayproof/certified.h>

#include <cstdio>

#include "checks.h"

namespace {

int expect(const char* what, rayproof::Contact got, double t, rayproof::Contact want, double want_t) {
  if (got == want && t == want_t) return 0;
  std::printf("certified: %s gave %s %g, want %s %g\n", what, to_string(got).data(), t, to_string(want).data(), want_t);
  return 1;
}

}  // namespace

int check_certified() {
  using namespace rayproof;
  using V = Vec3<double>;
  int failures = 0;
  failures += expect("plane", certified::intersect(Ray<double>{V{0, 0, 0}, V{0, 0, 1}}, Plane<double>{V{0, 0, 3}, V{0, 0, 1}}).contact,
                     3, Contact::hit, 3);
  const auto sphere = certified::intersect(Ray<double>{V{-3, 1, 0}, V{1, 0, 0}}, Sphere<double>{V{0, 0, 0}, 1});
  failures += expect("sphere", sphere.contact, sphere.t, Contact::tangent, 3);
  const auto ell = certified::intersect(Ray<double>{V{-4, 0, 2}, V{1, 0, 0}}, Ellipsoid<double>{V{0, 0, 0}, V{2, 3, 2}});
  failures += expect("ellipsoid", ell.contact, ell.t, Contact::tangent, 4);
  const auto tri = certified::intersect(Ray<double>{V{2, 0, 5}, V{0, 0, -1}}, Triangle<double>{V{0, 0, 0}, V{4, 0, 0}, V{0, 4, 0}});
  failures += expect("triangle", tri.contact, tri.t, Contact::edge, 5);
  if (tri.b1 != 0.5 || tri.b2 != 0) {
    std::printf("certified: triangle barycentrics %g %g, want 0.5 0\n", tri.b1, tri.b2);
    ++failures;
  }
  const auto box = certified::intersect(Ray<double>{V{-1, 0, 0.5}, V{1, 1, 0}}, Box<double>{V{0, 0, 0}, V{1, 1, 1}});
  failures += expect("box", box.contact, box.t, Contact::graze, 1);
  const auto disk = certified::intersect(Ray<double>{V{3, 4, 2}, V{0, 0, -1}}, Disk<double>{V{0, 0, 0}, V{0, 0, 1}, 5});
  failures += expect("disk", disk.contact, disk.t, Contact::rim, 2);
  std::printf("certified: 6 kinds checked, %d failures\n", failures);
  return failures;
}
