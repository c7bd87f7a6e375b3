/// The float and double methods: the worked problems' formulas (rayproof/*.h) in each precision.
#include "methods/method.h"
#include "methods/primitive_of.h"
#include "rayproof/triangle.h"

namespace rayproof {

namespace {

template <class T>
io::CaseResult textbook(const io::Case& c, TriangleMethod tm) {
  const auto ray = ray_of<T>(c);
  auto out = [&](auto h) { return make_result(c.kind, h.contact, double(h.t), double(h.t2)); };
  switch (c.kind) {
    case io::Kind::plane: return out(intersect(ray, plane_of<T>(c)));
    case io::Kind::sphere: return out(intersect(ray, sphere_of<T>(c)));
    case io::Kind::ellipsoid: return out(intersect(ray, ellipsoid_of<T>(c)));
    case io::Kind::triangle: return out(intersect(ray, triangle_of<T>(c), tm));
    case io::Kind::box: return out(intersect(ray, box_of<T>(c)));
    case io::Kind::disk: return out(intersect(ray, disk_of<T>(c)));
    case io::Kind::tritri: break;  // not registered for pairs (tritri_methods.cpp)
  }
  return {Contact::error};
}


}  // namespace

void register_fast_methods(MethodRegistry& reg) {
  const std::vector<io::Kind> all(io::kAllKinds.begin(), io::kAllKinds.end());
  const std::vector<io::Kind> tri{io::Kind::triangle};
  reg.add({"float", "worked problems' formulas in float (Möller–Trumbore for triangles), float inputs",
           Precision::float32, all, [](const io::Case& c) { return textbook<float>(c, TriangleMethod::moller_trumbore); }, {},
           {}, {}, {}, {FastKernel::mt_float, false}});
  reg.add({"double", "worked problems' formulas in double (Möller–Trumbore for triangles)", Precision::float64, all,
           [](const io::Case& c) { return textbook<double>(c, TriangleMethod::moller_trumbore); }, {}, {}, {}, {},
           {FastKernel::mt_double, false}});
  reg.add({"cramer-float", "triangle by Cramer's rule (M = [-D, E1, E2]) in float, float inputs", Precision::float32,
           tri, [](const io::Case& c) { return textbook<float>(c, TriangleMethod::cramer); }, {}, {}, {}, {},
           {FastKernel::cramer_float, false}});
  reg.add({"cramer-double", "triangle by Cramer's rule in double", Precision::float64, tri,
           [](const io::Case& c) { return textbook<double>(c, TriangleMethod::cramer); }, {}, {}, {}, {},
           {FastKernel::cramer_double, false}});
}

}  // namespace rayproof
