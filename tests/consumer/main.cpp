// A downstream project using the installed header-only kernels.
#include <rayproof/box.h>
#include <rayproof/triangle.h>

#include <cstdio>

int main() {
  using namespace rayproof;
  const Ray<double> ray{{0, 0, 0}, {1, 1, 1}};
  const auto tri = intersect(ray, Triangle<double>{{2, 4, 2}, {5, -7, -1}, {0, -9, 4}});
  const auto box = intersect(Ray<double>{{-3, 4, 5}, {1, -1, -2}}, Box<double>{{-2, -2, -2}, {2, 2, 2}});
  std::printf("%s %g %s %g %g\n", to_string(tri.contact).data(), tri.t, to_string(box.contact).data(), box.t, box.t2);
  return (tri.contact == Contact::interior && tri.t == 2 && box.t == 2 && box.t2 == 3.5) ? 0 : 1;
}
