/// The exact method: ground truth of docs/cases.md, on a case file's fields. The case becomes a typed
/// ray and primitive (exactly: the fields are doubles) and goes through rayproof::exact::intersect
/// (rayproof/verify/exact.h: the exact algorithm of src/exact/algorithms.h on CGAL's kernel, exact_cgal.cpp).
#include "verify/exact_method.h"

#include <cmath>

#include "methods/primitive_of.h"
#include "rayproof/verify/exact.h"

namespace rayproof::verify {

io::CaseResult exact_classify(const io::Case& c) {
  const Ray<double> ray = ray_of<double>(c);
  auto result = [&](const auto& h) { return make_result(c.kind, h.contact, h.t, h.t2); };
  switch (c.kind) {
    case io::Kind::plane: return result(exact::intersect(ray, plane_of<double>(c)));
    case io::Kind::sphere: return result(exact::intersect(ray, sphere_of<double>(c)));
    case io::Kind::ellipsoid: return result(exact::intersect(ray, ellipsoid_of<double>(c)));
    case io::Kind::triangle: return result(exact::intersect(ray, triangle_of<double>(c)));
    case io::Kind::box: return result(exact::intersect(ray, box_of<double>(c)));
    case io::Kind::disk: return result(exact::intersect(ray, disk_of<double>(c)));
    case io::Kind::tritri:
      return io::pair_result(to_contact(exact::tritri(first_triangle_of<double>(c), second_triangle_of<double>(c))));
  }
  return {Contact::error, std::nullopt, std::nullopt};
}

std::optional<std::array<double, 2>> exact_barycentrics(const io::Case& c) {
  if (c.kind != io::Kind::triangle) return std::nullopt;
  // exact::intersect carries b1, b2 (rounded to nearest) for a contact of the line: interior, edge,
  // vertex or behind; NaN otherwise.
  const TriangleHit<double> h = exact::intersect(ray_of<double>(c), triangle_of<double>(c));
  if (std::isnan(h.b1) || std::isnan(h.b2)) return std::nullopt;
  return std::array<double, 2>{h.b1, h.b2};
}

void register_exact_method(MethodRegistry& reg) {
  reg.add({"exact",
           "ground truth: exact rationals (CGAL Gmpq) decide the class; T, T2 rounded to nearest (MPFR, "
           "checked exactly); triangle pairs by CGAL's Triangle_3 intersection",
           Precision::float64, std::vector<io::Kind>(io::kCaseKinds.begin(), io::kCaseKinds.end()), exact_classify, {}, {}, {},
           exact_promises()});
}

}  // namespace rayproof::verify
