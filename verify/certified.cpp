/// The certified method: floating-point filters with error bounds, exact fallback (GMP via
/// exact_classify) when a bound cannot decide a sign or pin a t to one ulp.
#include "verify/certified.h"

#include "methods/primitive_of.h"
#include "rayproof/certified_box.h"
#include "rayproof/certified_planar.h"
#include "rayproof/certified_quadric.h"
#include "rayproof/certified_triangle.h"
#include "verify/exact.h"

namespace rayproof::verify {

namespace {

// Per thread, so that a caller can attribute fallbacks to its own cases while other threads run.
thread_local std::uint64_t g_fallbacks = 0;

}  // namespace

std::optional<Hit<double>> certified_filter(const io::Case& c) {
  const Ray<double> ray = ray_of<double>(c);
  switch (c.kind) {
    case io::Kind::plane: return certified::plane(ray, plane_of<double>(c));
    case io::Kind::sphere: return certified::sphere(ray, sphere_of<double>(c));
    case io::Kind::ellipsoid: return certified::ellipsoid(ray, ellipsoid_of<double>(c));
    case io::Kind::triangle: return certified::triangle(ray, triangle_of<double>(c));
    case io::Kind::box: return certified::box(ray, box_of<double>(c));
    case io::Kind::disk: return certified::disk(ray, disk_of<double>(c));
  }
  return std::nullopt;
}

io::CaseResult certified_classify(const io::Case& c, std::uint64_t* fallbacks) {
  if (const auto h = certified_filter(c)) return make_result(c.kind, h->contact, h->t, h->t2);
  if (fallbacks) ++*fallbacks;
  return exact_classify(c);
}

std::uint64_t certified_fallbacks() { return g_fallbacks; }

void register_certified_method(MethodRegistry& reg) {
  reg.add({"certified",
           "exact class, T within 1 ulp: error-bounded filters in extended precision, exact (GMP) fallback",
           Precision::float64, std::vector<io::Kind>(io::kAllKinds.begin(), io::kAllKinds.end()),
           [](const io::Case& c) {
             if (const auto h = certified_filter(c)) return make_result(c.kind, h->contact, h->t, h->t2);
             ++g_fallbacks;
             return exact_classify(c);
           },
           certified_fallbacks});
}

}  // namespace rayproof::verify
