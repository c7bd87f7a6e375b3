/// The two instantiations of the exact algorithm (src/exact/algorithms.h) against each other:
/// the ground truth rayproof::exact::intersect (rayproof_verify, on CGAL's Gmpq and Simple_cartesian
/// kernel) and the certified tier's exact fallback rayproof::certified::fallback::intersect
/// (rayproof_certified, on gmpxx's mpq_class and its own vector operations, no CGAL). The algorithm
/// and the MPFR rounding are one code, so this checks the kernels: the number type and the point /
/// vector operations (dot, cross, determinant, sign, comparison). Every field must agree bit for
/// bit: the class, t, t2, the triangle barycentrics b1, b2 (NaN where the class carries none, +0.0
/// and -0.0 told apart), on every generator family (float- and double-built, fixed seed and count)
/// and on data/sample.txt.
#include <gtest/gtest.h>

#include <cstddef>
#include <map>
#include <string>

#include "api_cases.h"
#include "io/case_file.h"
#include "rayproof/verify/exact.h"
#include "exact/fallback.h"

namespace rayproof {
namespace {

using api_test::same;

constexpr std::size_t kCasesPerFamily = 150;  // per precision
constexpr std::uint64_t kSeed = 20261130;

std::string show(const Hit<double>& h) {
  return std::string(to_string(h.contact)) + " t=" + io::format_double(h.t) + " t2=" + io::format_double(h.t2);
}
std::string show(const TriangleHit<double>& h) {
  return std::string(to_string(h.contact)) + " t=" + io::format_double(h.t) + " t2=" + io::format_double(h.t2) +
         " b1=" + io::format_double(h.b1) + " b2=" + io::format_double(h.b2);
}

bool agree(const Hit<double>& a, const Hit<double>& b) {
  return a.contact == b.contact && same(a.t, b.t) && same(a.t2, b.t2);
}
bool agree(const TriangleHit<double>& a, const TriangleHit<double>& b) {
  return a.contact == b.contact && same(a.t, b.t) && same(a.t2, b.t2) && same(a.b1, b.b1) && same(a.b2, b.b2);
}

/// Compares the two on one case; counts the classes seen (so that the test can require coverage).
void crosscheck(const io::Case& c, std::map<Contact, std::size_t>& seen) {
  api_test::visit(c, [&](const auto& ray, const auto& prim) {
    const auto truth = exact::intersect(ray, prim);
    const auto fb = certified::fallback::intersect(ray, prim);
    ++seen[truth.contact];
    EXPECT_TRUE(agree(truth, fb)) << io::format_case(c) << "\n  exact (CGAL):       " << show(truth)
                                  << "\n  certified fallback: " << show(fb);
  });
}

TEST(ExactCrosscheck, EveryFamilyFloatAndDoubleBuilt) {
  std::map<Contact, std::size_t> seen;
  std::size_t cases = 0, ray_families = 0;
  for (const gen::Family& f : gen::families()) {
    if (f.kind == io::Kind::tritri) continue;  // pairs have no ray: tritri_test cross-checks them against CGAL
    ++ray_families;
    for (const auto p : {gen::Precision::float32, gen::Precision::float64})
      for (const io::Case& c : gen::generate(f, kCasesPerFamily, kSeed, p)) {
        crosscheck(c, seen);
        ++cases;
      }
  }
  EXPECT_EQ(cases, ray_families * 2 * kCasesPerFamily);
  // Coverage: every class the kernels construct answers for turns up (the families claim them).
  for (const Contact k : {Contact::hit, Contact::miss, Contact::behind, Contact::inside, Contact::tangent,
                          Contact::graze, Contact::rim, Contact::interior, Contact::edge, Contact::vertex,
                          Contact::parallel, Contact::coplanar, Contact::degenerate, Contact::invalid})
    EXPECT_GT(seen[k], 0U) << to_string(k);
}

TEST(ExactCrosscheck, Sample) {
  const api_test::Sample s = api_test::load_sample();
  std::map<Contact, std::size_t> seen;
  for (const io::Case& c : s.cases) crosscheck(c, seen);
  EXPECT_GT(seen.size(), 5U);
}

}  // namespace
}  // namespace rayproof
