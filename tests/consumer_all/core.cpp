// rayproof::core: the header-only kernels, on contacts whose answers are exact dyadic numbers.
#include <rayproof/box.h>
#include <rayproof/certified_triangle.h>
#include <rayproof/triangle.h>

#include <cstdio>

#include "checks.h"

int check_core() {
  using namespace rayproof;
  int failures = 0;
  // The ray through (2, 2, 2), an interior point of the triangle (barycentrics 1/4, 1/4, 1/2).
  const Triangle<double> tri{{2, 4, 2}, {5, -7, -1}, {0, -9, 4}};
  const auto hit = intersect(Ray<double>{{0, 0, 0}, {1, 1, 1}}, tri);
  if (hit.contact != Contact::interior || hit.t != 2) {
    std::printf("core: triangle gave %s %g, want interior 2\n", to_string(hit.contact).data(), hit.t);
    ++failures;
  }
  // The header-only certified filter decides it too (or says it cannot: nullopt).
  const auto cert = certified::triangle(Ray<double>{{0, 0, 0}, {1, 1, 1}}, tri);
  if (cert && (cert->contact != Contact::interior || cert->t != 2)) {
    std::printf("core: certified filter gave %s %g, want interior 2\n", to_string(cert->contact).data(), cert->t);
    ++failures;
  }
  const auto box = intersect(Ray<double>{{-3, 4, 5}, {1, -1, -2}}, Box<double>{{-2, -2, -2}, {2, 2, 2}});
  if (box.contact != Contact::hit || box.t != 2 || box.t2 != 3.5) {
    std::printf("core: box gave %s %g %g, want hit 2 3.5\n", to_string(box.contact).data(), box.t, box.t2);
    ++failures;
  }
  std::printf("core: kernels checked, %d failures\n", failures);
  return failures;
}
