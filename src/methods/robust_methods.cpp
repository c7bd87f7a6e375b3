/// The robust methods: the best-known floating-point method per kind, no exact arithmetic
/// (watertight triangles, stable quadrics, conservative slabs, FMA planes and disks), and the
/// triangle alternatives the report places beside them.
#include "methods/method.h"
#include "methods/primitive_of.h"
#include "rayproof/box_conservative.h"
#include "rayproof/disk_fma.h"
#include "rayproof/plane_fma.h"
#include "rayproof/quadric_stable.h"
#include "rayproof/triangle_baldwin_weber.h"
#include "rayproof/triangle_moller_trumbore.h"
#include "rayproof/triangle_plucker.h"
#include "rayproof/triangle_watertight.h"

namespace rayproof {

namespace {

template <class H>
io::CaseResult result_of(const io::Case& c, const H& h) {
  return make_result(c.kind, h.contact, double(h.t), double(h.t2));
}

template <class T>
io::CaseResult robust(const io::Case& c) {
  const auto ray = ray_of<T>(c);
  switch (c.kind) {
    case io::Kind::plane: return result_of(c, intersect_fma(ray, plane_of<T>(c)));
    case io::Kind::sphere: return result_of(c, intersect_stable(ray, sphere_of<T>(c)));
    case io::Kind::ellipsoid: return result_of(c, intersect_stable(ray, ellipsoid_of<T>(c)));
    case io::Kind::triangle: return result_of(c, intersect_watertight<T, double>(ray, triangle_of<T>(c)));
    case io::Kind::box: return result_of(c, intersect_conservative(ray, box_of<T>(c)));
    case io::Kind::disk: return result_of(c, intersect_fma(ray, disk_of<T>(c)));
    case io::Kind::tritri: break;  // not registered for pairs (tritri_methods.cpp)
  }
  return {Contact::error};
}

}  // namespace

void register_robust_methods(MethodRegistry& reg) {
  const std::vector<io::Kind> all(io::kAllKinds.begin(), io::kAllKinds.end());
  const std::vector<io::Kind> tri{io::Kind::triangle};
  reg.add({"robust",
           "float inputs and arithmetic: watertight triangles (Woop et al. 2013), stable quadrics (RT Gems 7), "
           "conservative slabs (Ize 2013), FMA planes and disks",
           Precision::float32, all, robust<float>, {}, {}, {},
           // Triangles: the watertight test with bounded zeros (triangle_watertight.h derives why
           // it misses no triangle the ray meets at t > 0 off its plane; before them it missed 3 in
           // a 94.7M-case fuzz); boxes: the conservative slabs miss none. Quadrics, planes and disks
           // rounded in float miss near tangency and rims, so nothing is promised there.
           {{io::Kind::triangle, Promise{false, Promise::NoFalseMiss::ahead, {}}},
            {io::Kind::box, Promise{false, Promise::NoFalseMiss::all, {}}}},
           {FastKernel::robust, true}});
  // In double, with bounded zeros too, triangles at t > 0 are still missed where the front door's
  // double normal underflows to zero or products overflow (measured: 960 of 5000 on
  // tri_extreme_scale, `gen all --precision double`), so only the conservative slabs' promise carries over.
  reg.add({"robust-double", "the robust kernels in double", Precision::float64, all, robust<double>, {}, {}, {},
           {{io::Kind::box, Promise{false, Promise::NoFalseMiss::all, {}}}}});
  reg.add({"watertight-float", "Woop, Benthin & Wald 2013 entirely in float (robust runs it in double)",
           Precision::float32, tri,
           [](const io::Case& c) { return result_of(c, intersect_watertight<float, float>(ray_of<float>(c), triangle_of<float>(c))); },
           {}, {}, {}, {}, {FastKernel::watertight_float, true}});
  // The mesh tool's watertight (`cast --method watertight`): the same test in double on the
  // scene's double inputs, with conservative boxes (Ize 2013) as its guarantee needs.
  reg.add({"watertight", "Woop, Benthin & Wald 2013 in double on double inputs (the BVH caster's watertight)",
           Precision::float64, tri,
           [](const io::Case& c) { return result_of(c, intersect_watertight<double, double>(ray_of<double>(c), triangle_of<double>(c))); },
           {}, {}, {}, {}, {FastKernel::watertight_double, true}});
  // The kernel robust ran before its bounded zeros (triangle_watertight.h), kept for comparison:
  // verify, fuzz and report place it beside robust in one run.
  reg.add({"watertight-double", "Woop, Benthin & Wald 2013 in double on float inputs, exact zeros (robust before bounded zeros)",
           Precision::float32, tri,
           [](const io::Case& c) {
             return result_of(c, intersect_watertight<float, double, EdgeZeros::exact>(ray_of<float>(c), triangle_of<float>(c)));
           },
           {}});
  reg.add({"mt-double", "Möller–Trumbore computed in double on float inputs", Precision::float32, tri,
           [](const io::Case& c) { return result_of(c, intersect_moller_trumbore(ray_of<double>(c), triangle_of<double>(c))); },
           {}});
  reg.add({"baldwin-weber", "Baldwin & Weber 2016 precomputed transform, float", Precision::float32, tri,
           [](const io::Case& c) { return result_of(c, intersect_baldwin_weber(ray_of<float>(c), triangle_of<float>(c))); },
           {}});
  reg.add({"plucker", "Plücker edge tests as in Embree's robust mode, float", Precision::float32, tri,
           [](const io::Case& c) { return result_of(c, intersect_plucker(ray_of<float>(c), triangle_of<float>(c))); },
           {}});
}

}  // namespace rayproof
