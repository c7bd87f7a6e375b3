// The adversarial case generator: determinism, the classes each family claims (checked by the exact
// method), float-exact output, and the `rayproof gen` command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "cli_support.h"
#include "gen/families.h"
#include "gen/rng.h"
#include "verify/exact_method.h"

namespace {

using rayproof::Contact;
using rayproof::gen::Family;
using rayproof::gen::Precision;
namespace gen = rayproof::gen;
namespace io = rayproof::io;
using rayproof::testing::run_rayproof;

std::string text_of(const std::vector<io::Case>& cases) {
  std::string s;
  for (const auto& c : cases) s += io::format_case(c) + "\n";
  return s;
}

std::uint64_t fnv(const std::string& s) { return gen::fnv1a64(s); }

// Pinned output of GenDeterminism.GoldenOutput (seed 1, 20 cases of every family).
const std::string kGoldenFirstTriEdge =
    "triangle 13568.0 5248.0 0.0 32.0 0.0 0.0 11264.0 -3072.0 -5120.0 14336.0 -8192.0 7168.0 14336.0 7168.0 -1024.0\n";
constexpr std::uint64_t kGolden64 = 3726296225344349183ULL;
constexpr std::uint64_t kGolden32 = 2579560059537141559ULL;

/// x is exactly a float: k 2^q with |k| < 2^24 and q >= -149, within the float range. Independent
/// of float conversions (which a compiler could get wrong, see src/gen/build.h).
bool is_float_exact(double x) {
  if (!std::isfinite(x) || x == 0) return true;
  if (std::fabs(x) > 0x1.fffffep+127) return false;
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, 0.5 <= |m| < 1
  const double k = std::ldexp(x, -std::max(e - 24, -149));
  return k == std::trunc(k);
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

}  // namespace

TEST(GenRng, MatchesTheReferenceImplementations) {
  // splitmix64.c and xoshiro256starstar.c (prng.di.unimi.it), seeded as Rng does.
  std::uint64_t x = 0;
  EXPECT_EQ(gen::splitmix64(x), 16294208416658607535ULL);
  EXPECT_EQ(gen::splitmix64(x), 7960286522194355700ULL);
  gen::Rng r(42);
  EXPECT_EQ(r.next(), 1546998764402558742ULL);
  EXPECT_EQ(r.next(), 6990951692964543102ULL);
  EXPECT_EQ(r.next(), 12544586762248559009ULL);
}

TEST(GenRng, MappingsStayInRange) {
  gen::Rng r(7);
  for (int i = 0; i < 10000; ++i) {
    const double u = r.unit();
    ASSERT_TRUE(u >= 0 && u < 1);
    const double s = r.sym();
    ASSERT_TRUE(s >= -1 && s < 1);
    const auto k = r.range(-3, 5);
    ASSERT_TRUE(k >= -3 && k <= 5);
    ASSERT_LT(r.below(7), 7u);
  }
}

TEST(GenFamilies, NamesAreUniqueAndFindable) {
  std::set<std::string> names;
  for (const auto& f : gen::families()) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    EXPECT_EQ(gen::find_family(f.name), &f);
    EXPECT_FALSE(f.stresses.empty()) << f.name;
    EXPECT_FALSE(f.classes.empty()) << f.name;
  }
  EXPECT_EQ(gen::find_family("no_such_family"), nullptr);
  for (const char* want : {"tri_generic", "tri_edge", "tri_vertex", "tri_offset_big", "tri_coplanar", "tri_degenerate",
                           "sph_tangent_exact", "sph_on_surface", "ell_stiff", "box_graze", "box_axis_parallel",
                           "plane_exact", "disk_rim", "invalid"})
    EXPECT_NE(gen::find_family(want), nullptr) << want;
}

TEST(GenDeterminism, SameSeedSameBytesOtherSeedOtherBytes) {
  for (const auto& f : gen::families()) {
    for (Precision p : {Precision::float64, Precision::float32}) {
      const std::string a = text_of(gen::generate(f, 40, 12345, p));
      EXPECT_EQ(a, text_of(gen::generate(f, 40, 12345, p))) << f.name;
      EXPECT_NE(a, text_of(gen::generate(f, 40, 12346, p))) << f.name;
    }
  }
}

TEST(GenDeterminism, FewerCasesAreAPrefixOfMore) {
  for (const auto& f : gen::families()) {
    const std::string few = text_of(gen::generate(f, 7, 99, Precision::float64));
    const std::string more = text_of(gen::generate(f, 30, 99, Precision::float64));
    EXPECT_EQ(more.compare(0, few.size(), few), 0) << f.name;
  }
}

// Pinned output: the bytes must be the same on every machine and compiler. Changing a family on
// purpose changes these; update them then (and say so: old seeds give new cases).
TEST(GenDeterminism, GoldenOutput) {
  std::string all64, all32;
  for (const auto& f : gen::families()) {
    // The ray families' pinned bytes; the triangle-pair families are tritri_families.cpp's pairs
    // (tritri_test checks the case lines are those pairs).
    if (f.kind == io::Kind::tritri) continue;
    all64 += text_of(gen::generate(f, 20, 1, Precision::float64));
    all32 += text_of(gen::generate(f, 20, 1, Precision::float32));
  }
  const auto first = text_of(gen::generate(*gen::find_family("tri_edge"), 1, 1, Precision::float64));
  EXPECT_EQ(first, kGoldenFirstTriEdge);
  EXPECT_EQ(fnv(all64), kGolden64) << "hash of double output changed";
  EXPECT_EQ(fnv(all32), kGolden32) << "hash of float output changed";
}

TEST(GenCases, CarryTheirFamilyAndKind) {
  for (const auto& f : gen::families()) {
    for (const auto& c : gen::generate(f, 50, 3, Precision::float64)) {
      EXPECT_EQ(c.family, f.name);
      EXPECT_EQ(c.line, 0u);
      if (!f.every_kind) {
        EXPECT_EQ(c.kind, f.kind) << f.name;
      }
    }
  }
  std::set<io::Kind> kinds;
  for (const auto& c : gen::generate(*gen::find_family("invalid"), 200, 3, Precision::float64)) kinds.insert(c.kind);
  EXPECT_EQ(kinds.size(), io::kAllKinds.size()) << "invalid cases cover every kind";
}

TEST(GenCases, TextReadsBackToTheSameDoubles) {
  for (const auto& f : gen::families()) {
    for (Precision p : {Precision::float64, Precision::float32}) {
      for (const auto& c : gen::generate(f, 50, 5, p)) {
        std::string family;
        const auto entry = io::parse_case_line(io::format_case(c), 1, family);
        ASSERT_TRUE(entry.has_value());
        const auto* back = std::get_if<io::Case>(&*entry);
        ASSERT_NE(back, nullptr) << io::format_case(c);
        for (std::size_t i = 0; i < c.v.size(); ++i)
          ASSERT_TRUE(same_bits(back->v[i], c.v[i])) << f.name << " field " << i << ": " << io::format_case(c);
      }
    }
  }
}

TEST(GenCases, FloatExactnessCheckWorks) {
  EXPECT_TRUE(is_float_exact(0.1f));
  EXPECT_FALSE(is_float_exact(0.1));
  EXPECT_TRUE(is_float_exact(0x1p-149));
  EXPECT_FALSE(is_float_exact(0x1p-150));
  EXPECT_TRUE(is_float_exact(0x1.fffffep+127));
  EXPECT_FALSE(is_float_exact(0x1p+128));
  EXPECT_FALSE(is_float_exact(1 + 0x1p-24));
  EXPECT_TRUE(is_float_exact(16777215.0));
  EXPECT_FALSE(is_float_exact(16777217.0));
}

TEST(GenCases, FloatPrecisionEmitsOnlyFloats) {
  for (const auto& f : gen::families()) {
    for (const auto& c : gen::generate(f, 300, 11, Precision::float32)) {
      const io::Case rounded = io::round_to_float(c);
      for (int i = 0; i < io::field_count(c.kind); ++i) {
        const auto k = static_cast<std::size_t>(i);
        ASSERT_TRUE(is_float_exact(c.v[k])) << f.name << " field " << i << ": " << io::format_case(c);
        ASSERT_TRUE(same_bits(rounded.v[k], c.v[k])) << f.name << " field " << i << ": " << io::format_case(c);
      }
    }
  }
}

// The contract of every family: each case is in one of its classes under exact arithmetic, in
// either precision. For the exact-contact families (one class) that is every case in that class.
TEST(GenCases, EveryFamilyProducesTheClassesItClaims) {
  for (const auto& f : gen::families()) {
    for (Precision p : {Precision::float64, Precision::float32}) {
      std::map<Contact, int> seen;
      int shown = 0;
      for (const auto& c : gen::generate(f, 300, 2024, p)) {
        const io::CaseResult r = rayproof::verify::exact_classify(c);
        ++seen[r.contact];
        const bool ok = std::find(f.classes.begin(), f.classes.end(), r.contact) != f.classes.end();
        if (!ok && shown++ < 3)
          ADD_FAILURE() << f.name << (p == Precision::float32 ? " (float)" : " (double)") << ": " << io::format_case(c)
                        << " -> " << io::format_result(r);
        // In float precision the float-rounded case is the same case, so a float method sees it.
        if (p == Precision::float32) {
          EXPECT_EQ(rayproof::verify::exact_classify(io::round_to_float(c)), r);
        }
      }
      // A family about a situation produces more than one of its classes.
      if (f.classes.size() > 1) {
        EXPECT_GE(seen.size(), 2u) << f.name;
      }
    }
  }
}

TEST(GenCases, ExactContactFamiliesHoldTheirClass) {
  const std::map<std::string, Contact> exact = {
      {"tri_interior_exact", Contact::interior}, {"tri_edge", Contact::edge},
      {"tri_vertex", Contact::vertex},           {"tri_coplanar", Contact::coplanar},
      {"tri_parallel", Contact::parallel},       {"tri_degenerate", Contact::degenerate},
      {"tri_behind", Contact::behind},           {"sph_tangent_exact", Contact::tangent},
      {"ell_tangent_exact", Contact::tangent},   {"box_graze", Contact::graze},
      {"disk_rim", Contact::rim},                {"invalid", Contact::invalid}};
  for (const auto& [name, cls] : exact) {
    const Family* f = gen::find_family(name);
    ASSERT_NE(f, nullptr) << name;
    EXPECT_EQ(f->classes, std::vector<Contact>{cls}) << name;
  }
}

// --- the command line ---------------------------------------------------------------------------

TEST(GenCli, WritesFamilyCommentsAndCases) {
  const auto r = run_rayproof("gen tri_edge --count 5 --seed 9");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  int cases = 0, headers = 0;
  while (std::getline(in, line)) {
    if (line == "# family tri_edge") ++headers;
    else if (line.rfind("triangle ", 0) == 0) ++cases;
    else EXPECT_EQ(line[0], '#') << line;
  }
  EXPECT_EQ(headers, 1);
  EXPECT_EQ(cases, 5);
  EXPECT_EQ(r.out, run_rayproof("gen tri_edge --count 5 --seed 9").out);
  // The same text as the library's.
  EXPECT_NE(r.out.find(text_of(gen::generate(*gen::find_family("tri_edge"), 5, 9, Precision::float64))),
            std::string::npos);
}

TEST(GenCli, AllGivesEveryFamilyAndItsOwnCases) {
  const auto r = run_rayproof("gen all --count 3 --precision float");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& f : gen::families()) {
    EXPECT_NE(r.out.find("# family " + f.name + "\n" + text_of(gen::generate(f, 3, 1, Precision::float32))),
              std::string::npos)
        << f.name;
  }
}

TEST(GenCli, ListsFamilies) {
  const auto r = run_rayproof("gen --list");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const auto& f : gen::families()) EXPECT_NE(r.out.find(f.name), std::string::npos) << f.name;
}

TEST(GenCli, RefusesBadArguments) {
  auto r = run_rayproof("gen no_such_family");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown family 'no_such_family'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tri_edge"), std::string::npos) << "lists the known families: " << r.err;
  EXPECT_EQ(r.out, "");
  for (const char* count : {"0", "-1", "10000001", "abc", "1e9", "99999999999999999999999"}) {
    r = run_rayproof(std::string("gen tri_edge --count ") + count);
    EXPECT_EQ(r.status, 2) << count;
    EXPECT_NE(r.err.find("--count must be"), std::string::npos) << count << ": " << r.err;
    EXPECT_EQ(r.out, "") << count;
  }
  r = run_rayproof("gen all --count 1000000");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  r = run_rayproof("gen tri_edge --precision half");
  EXPECT_EQ(r.status, 2);
  r = run_rayproof("gen tri_edge --seed -4");
  EXPECT_EQ(r.status, 2);
  r = run_rayproof("gen");
  EXPECT_EQ(r.status, 2);
}
