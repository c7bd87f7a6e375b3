/// The certified method on case files: rayproof::certified's filters (header-only) first, its exact
/// fallback (certified::fallback, GMP, src/exact/fallback.h) when they cannot decide: the same
/// implementation as rayproof::certified::intersect, on a case's fields. It is judged against the
/// `exact` method (CGAL): separate filters, and for the fallback the same exact algorithm
/// (src/exact/algorithms.h) on CGAL's kernel instead of gmpxx.
#include "verify/certified_method.h"

#include "methods/primitive_of.h"
#include "rayproof/certified/intersect.h"
#include "rayproof/certified/tritri.h"
#include "exact/fallback.h"

namespace rayproof::verify {

namespace {

// Per thread, so that a caller can attribute fallbacks to its own cases while other threads run.
thread_local std::uint64_t g_fallbacks = 0;

}  // namespace

std::optional<Hit<double>> certified_filter(const io::Case& c) {
  const Ray<double> ray = ray_of<double>(c);
  switch (c.kind) {
    case io::Kind::plane: return certified::try_intersect(ray, plane_of<double>(c));
    case io::Kind::sphere: return certified::try_intersect(ray, sphere_of<double>(c));
    case io::Kind::ellipsoid: return certified::try_intersect(ray, ellipsoid_of<double>(c));
    // The method reports no barycentrics: the triangle filter without them (certified_triangle.h).
    case io::Kind::triangle: return certified::triangle(ray, triangle_of<double>(c));
    case io::Kind::box: return certified::try_intersect(ray, box_of<double>(c));
    case io::Kind::disk: return certified::try_intersect(ray, disk_of<double>(c));
    case io::Kind::tritri: break;  // certified_classify
  }
  return std::nullopt;
}

io::CaseResult certified_classify(const io::Case& c, std::uint64_t* fallbacks) {
  if (c.kind == io::Kind::tritri) {
    // The filtered signs (header-only) first; GMP only where one of them needs it.
    const Triangle<double> a = first_triangle_of<double>(c), b = second_triangle_of<double>(c);
    if (const auto k = certified::try_tritri(a, b)) return io::pair_result(to_contact(*k));
    if (fallbacks) ++*fallbacks;
    return io::pair_result(to_contact(certified::tritri(a, b)));
  }
  if (const auto h = certified_filter(c)) return make_result(c.kind, h->contact, h->t, h->t2);
  if (fallbacks) ++*fallbacks;
  const Ray<double> ray = ray_of<double>(c);
  auto result = [&](const auto& h) { return make_result(c.kind, h.contact, h.t, h.t2); };
  switch (c.kind) {
    case io::Kind::plane: return result(certified::fallback::intersect(ray, plane_of<double>(c)));
    case io::Kind::sphere: return result(certified::fallback::intersect(ray, sphere_of<double>(c)));
    case io::Kind::ellipsoid: return result(certified::fallback::intersect(ray, ellipsoid_of<double>(c)));
    case io::Kind::triangle: return result(certified::fallback::intersect(ray, triangle_of<double>(c)));
    case io::Kind::box: return result(certified::fallback::intersect(ray, box_of<double>(c)));
    case io::Kind::disk: return result(certified::fallback::intersect(ray, disk_of<double>(c)));
    case io::Kind::tritri: break;  // above
  }
  return {Contact::invalid, std::nullopt, std::nullopt};
}

std::uint64_t certified_fallbacks() { return g_fallbacks; }

void register_certified_method(MethodRegistry& reg) {
  reg.add({"certified",
           "exact class, T within 1 ulp: error-bounded filters in extended precision, exact (GMP) fallback; "
           "triangle pairs by orientation signs (docs/tritri.md)",
           Precision::float64, std::vector<io::Kind>(io::kCaseKinds.begin(), io::kCaseKinds.end()),
           [](const io::Case& c) { return certified_classify(c, &g_fallbacks); }, certified_fallbacks, {}, {},
           exact_promises(), {FastKernel::certified, true}});
}

}  // namespace rayproof::verify
