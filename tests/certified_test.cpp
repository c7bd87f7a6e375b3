/// The certified method against the exact one: same class on every case, T and T2 within one
/// double ulp, on data/sample.txt and on every generator family; plus worked examples per kind.
#include "verify/certified.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "gen/families.h"
#include "io/case_file.h"
#include "verify/differential.h"
#include "verify/exact.h"

using namespace rayproof;

namespace {

io::Case parse(const std::string& line) {
  std::string family;
  const auto e = io::parse_case_line(line, 1, family);
  return std::get<io::Case>(*e);
}

/// Empty when certified agrees with exact on c; else a description.
std::string disagreement(const io::Case& c) {
  const io::CaseResult got = verify::certified_classify(c), want = verify::exact_classify(c);
  if (got.contact == want.contact && verify::t_error_ulps(got, want, Precision::float64) <= 1) return {};
  return io::format_case(c) + " got " + io::format_result(got) + " want " + io::format_result(want);
}

}  // namespace

TEST(Certified, WorkedExamples) {
  auto run = [](const std::string& s) { return io::format_result(verify::certified_classify(parse(s))); };
  EXPECT_EQ(run("ellipsoid 0 0 0 1 1 0 2 2 0 2 1 2"), "hit 1.105572809000084 2.8944271909999157");
  EXPECT_EQ(run("box -3 4 5 1 -1 -2 -2 -2 -2 2 2 2"), "hit 2.0 3.5");
  EXPECT_EQ(run("triangle 0 0 0 1 1 1 2 2 2 3 7 -1 0 9 -4"), "vertex 2.0 -");
  EXPECT_EQ(run("triangle 0 0 1 1 1 0 3 3 1 7 7 1 0 -9 -4"), "coplanar 3.0 7.0");
  EXPECT_EQ(run("plane 0 0 0 1 1 0 0 0 5 0 0 1"), "parallel - -");
  EXPECT_EQ(run("sphere 0 0 0 0 0 1 0 0 5 1"), "hit 4.0 6.0");
  EXPECT_EQ(run("disk 0 0 0 0 0 1 0 0 5 0 0 1 2"), "hit 5.0 -");
  EXPECT_EQ(run("sphere 0 0 0 0 0 1 0 0 5 nan"), "invalid - -");
}

TEST(Certified, FilterDecidesGenericCasesWithoutFallback) {
  for (const char* s : {"triangle 0.1 0.2 0 0.3 0.1 1 -1 -1 3 1 -1 3 0 1 3", "sphere 0.1 0 0 0.2 0.3 1 0 0 5 1.5",
                        "box -3 4 5 1 -1 -2 -2 -2 -2 2 2 2", "plane 0.1 0 0 1 1 3 0 0 5 0.1 0.2 1"}) {
    EXPECT_TRUE(verify::certified_filter(parse(s)).has_value()) << s;
  }
}

TEST(Certified, EqualsExactOnEverySampleLine) {
  std::ifstream in(std::string(RAYPROOF_DATA_DIR) + "/sample.txt");
  std::ifstream expected(std::string(RAYPROOF_DATA_DIR) + "/sample.expected");
  ASSERT_TRUE(in && expected);
  std::size_t n = 0;
  std::string want_line;
  for (const auto& e : io::read_cases(in)) {
    ASSERT_TRUE(std::getline(expected, want_line));
    const auto* c = std::get_if<io::Case>(&e);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(disagreement(*c), "");
    const auto want = io::parse_result(want_line);
    ASSERT_TRUE(want.has_value()) << want_line;
    EXPECT_EQ(verify::certified_classify(*c).contact, want->contact) << io::format_case(*c);
    ++n;
  }
  EXPECT_EQ(n, 602u);
}

/// 6,000 cases of every family (~190k), double and float precision: no disagreement.
TEST(Certified, EqualsExactOnEveryGeneratedFamily) {
  std::size_t cases = 0, fallbacks = 0, bad = 0;
  for (const auto& f : gen::families()) {
    for (auto p : {gen::Precision::float64, gen::Precision::float32}) {
      for (const io::Case& c : gen::generate(f, 3000, 11, p)) {
        std::uint64_t fb = 0;
        const io::CaseResult got = verify::certified_classify(c, &fb), want = verify::exact_classify(c);
        fallbacks += fb;
        ++cases;
        if (got.contact != want.contact || verify::t_error_ulps(got, want, Precision::float64) > 1) {
          if (++bad <= 10) ADD_FAILURE() << f.name << ": " << io::format_case(c) << " got " << io::format_result(got)
                                         << " want " << io::format_result(want);
        }
      }
    }
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_GE(cases, 190000u);
  std::printf("certified: %zu cases, %zu fallbacks (%.1f%%)\n", cases, fallbacks, 100.0 * double(fallbacks) / double(cases));
}
