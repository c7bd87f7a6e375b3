/// The classic triangle/triangle tests as methods on `tritri` cases (docs/tritri.md): Möller 1997
/// and Guigue–Devillers 2003, in float (on the pair rounded to float) and in double. They answer
/// intersect-or-not only, so their answers are coarse (`hit`: the triangles meet, `miss`: they do
/// not) and are judged by whether the exact class meets (rayproof::meets). They promise nothing.
#include "methods/method.h"
#include "methods/primitive_of.h"
#include "rayproof/tritri.h"

namespace rayproof {

namespace {

template <class T>
io::CaseResult classic(const io::Case& c, TriTriMethod m) {
  return io::pair_coarse(tritri_intersect(first_triangle_of<T>(c), second_triangle_of<T>(c), m));
}

}  // namespace

void register_tritri_methods(MethodRegistry& reg) {
  const std::vector<io::Kind> pair{io::Kind::tritri};
  reg.add({"moller-float", "triangle pairs: Möller 1997's interval test in float, float inputs (meets or not)",
           Precision::float32, pair, [](const io::Case& c) { return classic<float>(c, TriTriMethod::moller); }, {}});
  reg.add({"moller-double", "triangle pairs: Möller 1997's interval test in double (meets or not)", Precision::float64,
           pair, [](const io::Case& c) { return classic<double>(c, TriTriMethod::moller); }, {}});
  reg.add({"gd-float", "triangle pairs: Guigue–Devillers 2003's orientation test in float, float inputs (meets or not)",
           Precision::float32, pair, [](const io::Case& c) { return classic<float>(c, TriTriMethod::guigue_devillers); },
           {}});
  reg.add({"gd-double", "triangle pairs: Guigue–Devillers 2003's orientation test in double (meets or not)",
           Precision::float64, pair, [](const io::Case& c) { return classic<double>(c, TriTriMethod::guigue_devillers); },
           {}});
}

}  // namespace rayproof
