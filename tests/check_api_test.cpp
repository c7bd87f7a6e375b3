// rayproof/verify/check.h: a user's typed C++ kernel through the checker of `rayproof check`.
#include "rayproof/verify/check.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "rayproof/certified/intersect.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_moller_trumbore.h"

namespace rayproof {
namespace {

std::size_t false_misses(const verify::KernelCheck& k, const std::string& family) {
  for (const auto& f : k.families)
    if (f.family == family) return f.false_misses;
  ADD_FAILURE() << "no family " << family;
  return 0;
}

TEST(CheckApi, NaiveFloatMollerTrumboreBreaksWatertightWithReproducers) {
  verify::KernelCheckOptions opt;
  opt.count = 400;
  opt.families = {"tri_edge", "tri_vertex", "tri_generic"};
  opt.watertight = true;
  const auto k = verify::check(verify::TriangleKernel<float>(intersect_moller_trumbore<float>), opt);
  ASSERT_EQ(k.families.size(), 3u);
  EXPECT_EQ(k.cases(), 1200u);
  EXPECT_GT(false_misses(k, "tri_edge") + false_misses(k, "tri_vertex"), 0u);
  ASSERT_EQ(k.promises.size(), 1u);
  EXPECT_EQ(k.promises[0].promise, "watertight");
  EXPECT_FALSE(k.promises[0].kept);
  EXPECT_FALSE(k.promises_kept());
  bool listed = false;
  for (const auto& r : k.reproducers)
    if (r.verdict == "false-miss") {
      listed = true;
      EXPECT_EQ(r.case_line.rfind("triangle ", 0), 0u) << r.case_line;
      EXPECT_NE(r.kernel_answer, r.exact_answer);
      EXPECT_EQ(r.exact_answer.find("miss"), std::string::npos) << r.exact_answer;
    }
  EXPECT_TRUE(listed);
}

TEST(CheckApi, CertifiedKeepsExactClassAndOneUlpOnEveryTriangleFamily) {
  verify::KernelCheckOptions opt;
  opt.count = 200;
  opt.exact_class = true;
  opt.max_ulps = 1;
  const auto k = verify::check(
      verify::TriangleKernel<double>([](const Ray<double>& r, const Triangle<double>& t) { return certified::intersect(r, t); }),
      opt);
  EXPECT_GT(k.families.size(), 10u);
  EXPECT_EQ(k.class_errors(), 0u);
  EXPECT_TRUE(k.promises_kept());
  for (const auto& f : k.families) EXPECT_LE(f.ulp_max, 1u) << f.family;
}

TEST(CheckApi, AThrowingKernelIsAFailureWithItsCaseNotAClassError) {
  verify::KernelCheckOptions opt;
  opt.count = 100;
  opt.families = {"sph_generic"};
  int calls = 0;
  const auto k = verify::check(verify::SphereKernel<double>([&](const Ray<double>& r, const Sphere<double>& s) {
                                 if (++calls == 10) throw std::runtime_error("boom");
                                 return intersect(r, s);
                               }),
                               opt);
  ASSERT_EQ(k.families.size(), 1u);
  EXPECT_EQ(k.families[0].cases, 100u);
  EXPECT_EQ(k.families[0].failures, 1u);
  bool found = false;
  for (const auto& r : k.reproducers)
    if (r.verdict == "kernel-failure: threw: boom") found = r.case_line.rfind("sphere ", 0) == 0;
  EXPECT_TRUE(found);
}

TEST(CheckApi, BadOptionsAreClearErrors) {
  const verify::TriangleKernel<double> mt(intersect_moller_trumbore<double>);
  verify::KernelCheckOptions opt;
  opt.families = {"no_such_family"};
  EXPECT_THROW((void)verify::check(mt, opt), std::invalid_argument);
  opt.families = {"sph_generic"};
  EXPECT_THROW((void)verify::check(mt, opt), std::invalid_argument);
  opt.families = {};
  opt.count = 0;
  EXPECT_THROW((void)verify::check(mt, opt), std::invalid_argument);
  EXPECT_THROW((void)verify::check(verify::TriangleKernel<double>{}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace rayproof
