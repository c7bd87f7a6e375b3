// Stability curves: the knob generators hold their knob value exactly and get
// their answers from exact; the break finder and every sentence from known tallies; the SVG; and
// `rayproof report --stability` writing its files.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <set>

#include "cli_support.h"
#include "gen/knobs.h"
#include "report/stability_report.h"
#include "report/stability_text.h"
#include "verify/exact_method.h"
#include "verify/stability.h"

using namespace rayproof;
using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::slurp;

namespace {

const gen::Knob& knob(const char* name) {
  const gen::Knob* k = gen::find_knob(name);
  EXPECT_NE(k, nullptr) << name;
  return *k;
}

std::vector<io::Case> cases(const char* name, int k, std::size_t n = 40) { return gen::generate_knob(knob(name), k, n, 7); }

using LD = long double;
struct V3 {
  LD x, y, z;
};
V3 at(const io::Case& c, std::size_t i) { return {c.v[i], c.v[i + 1], c.v[i + 2]}; }
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
LD dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
LD len(V3 a) { return std::sqrt(dot(a, a)); }

bool is_float(double x) { return static_cast<double>(static_cast<float>(x)) == x; }

/// A t that is an integer in [lo, hi].
bool integer_t(const io::CaseResult& r, double lo, double hi) {
  return r.t && *r.t == std::round(*r.t) && *r.t >= lo && *r.t <= hi;
}

}  // namespace

TEST(Knobs, DeterministicAndNamedBySteps) {
  for (const auto& k : gen::knobs()) {
    ASSERT_FALSE(k.exponents.empty()) << k.name;
    const int e = k.exponents[k.exponents.size() / 2];
    const auto a = gen::generate_knob(k, e, 5, 3), b = gen::generate_knob(k, e, 5, 3);
    ASSERT_EQ(a.size(), 5u);
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].v, b[i].v) << k.name;
      EXPECT_EQ(a[i].kind, k.kind);
      EXPECT_EQ(a[i].family, gen::step_name(k, e));
    }
    // The first cases of a longer run are the cases of a shorter one; another seed differs.
    EXPECT_EQ(gen::generate_knob(k, e, 9, 3)[4].v, a[4].v);
    EXPECT_NE(gen::generate_knob(k, e, 5, 4)[0].v, a[0].v) << k.name;
    const auto parsed = gen::parse_step_name(gen::step_name(k, e));
    ASSERT_TRUE(parsed);
    EXPECT_EQ(parsed->first, &k);
    EXPECT_EQ(parsed->second, e);
  }
  EXPECT_FALSE(gen::parse_step_name("offset@x"));
  EXPECT_FALSE(gen::parse_step_name("nope@3"));
  EXPECT_FALSE(gen::parse_step_name("offset"));
}

TEST(Knobs, OffsetOverSizeIsTwoToTheK) {
  for (int k : {0, 8, 24, 36}) {
    const double off = std::ldexp(1.0, k + 12), size = std::ldexp(1.0, 12);
    for (const auto& c : cases("offset", k)) {
      // Every position is the offset plus a lattice value (exact at these k): at most the size for
      // the vertices, at most 2^15 for the origin.
      for (std::size_t i : {0, 1, 2, 6, 7, 8, 9, 10, 11, 12, 13, 14}) {
        EXPECT_LE(std::fabs(std::fabs(c.v[i]) - off), i < 3 ? 8 * size : size) << k;
        if (k >= 4) {
          EXPECT_EQ(std::fmod(c.v[i] - std::copysign(off, c.v[i]), 1.0), 0.0);
        }
      }
      const auto r = verify::exact_classify(c);
      EXPECT_TRUE(r.contact == Contact::interior || r.contact == Contact::miss || r.contact == Contact::behind)
          << io::format_case(c);
      if (r.contact == Contact::interior) {
        EXPECT_TRUE(integer_t(r, 1, 8)) << io::format_case(c);
      }
    }
  }
}

TEST(Knobs, TriangleTiltIsExactlyTwoToTheK) {
  for (int k : {-1, -24, -53, -59}) {
    std::set<Contact> seen;
    for (const auto& c : cases("tilt_triangle", k)) {
      EXPECT_EQ(std::fabs(c.v[5]), std::ldexp(std::max(std::fabs(c.v[3]), std::fabs(c.v[4])), k));
      for (double x : c.v) EXPECT_TRUE(is_float(x));
      const auto r = verify::exact_classify(c);
      seen.insert(r.contact);
      if (r.contact == Contact::interior) {
        EXPECT_TRUE(integer_t(r, 1, 16)) << io::format_case(c);
      } else {
        EXPECT_TRUE(r.contact == Contact::miss || r.contact == Contact::behind) << io::format_case(c);
      }
    }
    EXPECT_TRUE(seen.count(Contact::interior)) << k;
    EXPECT_TRUE(seen.count(Contact::miss)) << k;
  }
}

TEST(Knobs, PlaneTiltIsTwoToTheKWithinAFactorFour) {
  for (int k : {-1, -9, -30}) {
    for (const auto& c : cases("tilt_plane", k)) {
      const V3 d = at(c, 3), n = at(c, 9);
      const LD sine = std::fabs(dot(n, d)) / (len(n) * len(d));
      EXPECT_GE(sine, std::ldexp(1.0L, k - 2)) << io::format_case(c);
      EXPECT_LE(sine, std::ldexp(1.0L, k + 2)) << io::format_case(c);
      const auto r = verify::exact_classify(c);
      EXPECT_TRUE(r.contact == Contact::hit || r.contact == Contact::behind) << io::format_case(c);
    }
  }
}

TEST(Knobs, SliverAspectIsBetweenTwoToTheKAndTwiceThat) {
  for (int k : {0, 6, 20}) {
    for (const auto& c : cases("sliver", k)) {
      const V3 a = at(c, 6), b = at(c, 9), d = at(c, 12);
      const LD area2 = len(cross(sub(b, a), sub(d, a)));
      LD longest = 0;
      for (const auto& e : {sub(b, a), sub(d, b), sub(a, d)}) longest = std::max(longest, len(e));
      const LD aspect = longest * longest / area2;  // the longest edge over its altitude
      if (k > 0) {
        EXPECT_GE(aspect, std::ldexp(1.0L, k) * (1 - 1e-9L));
        EXPECT_LT(aspect, std::ldexp(1.0L, k + 1));
      } else {
        EXPECT_LT(aspect, 4);  // at k = 0 the longest edge may be another one
      }
      const auto r = verify::exact_classify(c);
      EXPECT_NE(r.contact, Contact::degenerate);
      EXPECT_NE(r.contact, Contact::invalid);
    }
  }
}

TEST(Knobs, FarSmallDistanceOverSizeAndFloatExact) {
  for (int k : {4, 30, 40}) {
    const LD size = std::ldexp(1.0L, -k);
    std::set<Contact> seen;
    for (const auto& c : cases("far_small", k)) {
      for (double x : c.v) EXPECT_TRUE(is_float(x));
      const V3 o = at(c, 0), a = at(c, 6), b = at(c, 9), d = at(c, 12);
      for (const auto& e : {sub(b, a), sub(d, b), sub(a, d)}) EXPECT_LE(len(e), 4 * size);
      EXPECT_NEAR(static_cast<double>(len(sub(a, o))), 1.0, static_cast<double>(8 * size));  // 1 away, within the sizes
      seen.insert(verify::exact_classify(c).contact);
    }
    EXPECT_TRUE(seen.count(Contact::interior)) << k;
  }
}

TEST(Knobs, EllipsoidAxisRatioIsExactlyTwoToTheK) {
  for (int k : {0, 10, 40}) {
    for (const auto& c : cases("ellipsoid", k)) {
      const double hi = std::max({c.v[9], c.v[10], c.v[11]}), lo = std::min({c.v[9], c.v[10], c.v[11]});
      EXPECT_EQ(hi, std::ldexp(lo, k));
      for (double x : c.v) EXPECT_TRUE(is_float(x));
      const auto r = verify::exact_classify(c);
      EXPECT_TRUE(r.contact == Contact::hit || r.contact == Contact::miss) << io::format_case(c);
    }
  }
}

TEST(Knobs, MagnitudeScalesAnExactCaseByTwoToTheK) {
  for (int k : {0, 200, 1000, -200, -1074}) {
    const char* name = k >= 0 ? "magnitude_large" : "magnitude_small";
    for (const auto& c : cases(name, k)) {
      for (std::size_t i = 0; i < 15; ++i) {
        const double m = std::ldexp(c.v[i], -k);  // the lattice integer
        EXPECT_EQ(m, std::round(m)) << k;
        EXPECT_LT(std::fabs(m), 512) << k;
      }
      if (k < -1000) continue;  // exact there too, but the t would be a subnormal ratio
      const auto r = verify::exact_classify(c);
      if (r.contact == Contact::interior) {
        EXPECT_TRUE(integer_t(r, 1, 8)) << io::format_case(c);
      } else {
        EXPECT_EQ(r.contact, Contact::miss) << io::format_case(c);
      }
    }
  }
}

TEST(Knobs, TangencyGapIsExactlyTwoToTheKOfTheRadius) {
  for (int k : {-3, -20, -40}) {
    std::set<Contact> seen;
    for (const auto& c : cases("tangency", k)) {
      const double R = c.v[9];
      std::size_t along = 0;
      while (c.v[3 + along] == 0) ++along;
      double dist = -1;
      int off_axes = 0;
      for (std::size_t i = 0; i < 3; ++i)
        if (i != along && c.v[i] != c.v[6 + i]) dist = std::fabs(c.v[i] - c.v[6 + i]), ++off_axes;
      ASSERT_EQ(off_axes, 1) << io::format_case(c);
      EXPECT_EQ(std::fabs(dist - R), std::ldexp(R, k)) << io::format_case(c);
      const auto r = verify::exact_classify(c);
      EXPECT_EQ(r.contact, dist < R ? Contact::hit : Contact::miss) << io::format_case(c);
      seen.insert(r.contact);
    }
    EXPECT_EQ(seen.size(), 2u);
  }
}

// ---------------------------------------------------------------------------------------------
// Breaks and sentences from known tallies.

namespace {

/// A step of `cases` cases with `errors` false misses and the given t errors.
verify::StepTally step(int e, std::size_t cases, std::size_t errors, std::vector<std::uint64_t> ulps = {}) {
  verify::StepTally t;
  t.exponent = e;
  t.stats.cases = cases;
  t.stats.false_miss = errors;
  t.stats.ulps = std::move(ulps);
  return t;
}

verify::StabilityCurve curve(const std::string& knob, const std::string& method, Precision p,
                             std::vector<verify::StepTally> steps, Promise promise = {}) {
  verify::StabilityCurve c;
  c.knob = knob;
  c.method = method;
  c.precision = p;
  c.promise = promise;
  c.steps = std::move(steps);
  return c;
}

Promise exactness() { return Promise{true, Promise::NoFalseMiss::all, 1}; }

}  // namespace

TEST(StabilityBreaks, FirstStepAboveTheThresholds) {
  const auto c = curve("tilt_triangle", "float", Precision::float32,
                       {step(-1, 1000, 0, {0, 0, 1}), step(-3, 1000, 1, {0, 2, 2}), step(-5, 0, 0),
                        step(-7, 1000, 2, {5, 5, 5}), step(-9, 1000, 900, {})});
  const auto b = verify::find_break(c);
  ASSERT_TRUE(b.class_errors);
  EXPECT_EQ(*b.class_errors, -7);  // 1 of 1000 is 0.1%, not above it; 2 of 1000 is
  ASSERT_TRUE(b.t_error);
  EXPECT_EQ(*b.t_error, -3);  // median 2 ulps
  const auto none = verify::find_break(curve("tilt_triangle", "x", Precision::float64, {step(-1, 10, 0, {1})}));
  EXPECT_FALSE(none.class_errors);
  EXPECT_FALSE(none.t_error);
  EXPECT_EQ(*verify::find_break(c, 0.5).class_errors, -9);
}

TEST(StabilityText, CellsAndPredictions) {
  const auto& tilt = knob("tilt_triangle");
  EXPECT_EQ(report::pow2_text(-24), "2^-24");
  EXPECT_EQ(report::break_cell(tilt, -17), "2^-17");
  EXPECT_EQ(report::break_cell(tilt, std::nullopt), "never up to 2^-59");
  EXPECT_EQ(report::arithmetic_bits("float", Precision::float32, io::Kind::triangle), 24);
  EXPECT_EQ(report::arithmetic_bits("mt-double", Precision::float32, io::Kind::triangle), 53);
  EXPECT_EQ(report::arithmetic_bits("robust", Precision::float32, io::Kind::triangle), 53);
  EXPECT_EQ(report::arithmetic_bits("robust", Precision::float32, io::Kind::sphere), 24);
  EXPECT_EQ(report::prediction_cell(report::predict(tilt, "float", Precision::float32, {})), "2^-16 .. 2^-24");
  EXPECT_EQ(report::prediction_cell(report::predict(tilt, "double", Precision::float64, {})), "2^-45 .. 2^-53");
  EXPECT_EQ(report::prediction_cell(report::predict(tilt, "certified", Precision::float64, exactness())), "never in range");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("sliver"), "float", Precision::float32, {})), "");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("magnitude_large"), "float", Precision::float32, {})),
            "2^34 .. 2^43");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("magnitude_small"), "double", Precision::float64, {})),
            "2^-340 .. 2^-366");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("magnitude_large"), "mt-double", Precision::float32, {})),
            "never in range");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("tangency"), "float", Precision::float32, {})), "2^-19 .. 2^-23");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("tangency"), "robust", Precision::float32, {})), "never in range");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("offset"), "baldwin-weber", Precision::float32, {})), "2^0 .. 2^16");
  EXPECT_EQ(report::prediction_cell(report::predict(knob("offset"), "float", Precision::float32, {})), "never in range");
}

TEST(StabilityText, AgreementUsesTheIntervalBetweenSteps) {
  const auto& tilt = knob("tilt_triangle");
  const auto p = *report::predict(tilt, "float", Precision::float32, {});  // 2^-16 .. 2^-24
  auto at = [&](int last_clean, int first_broken) {
    const auto c = curve("tilt_triangle", "float", Precision::float32,
                         {step(last_clean, 100, 0), step(first_broken, 100, 50)});
    return report::agreement(tilt, c, verify::find_break(c), p);
  };
  EXPECT_EQ(at(-13, -15), report::Agreement::earlier);
  EXPECT_EQ(at(-15, -17), report::Agreement::as_predicted);
  EXPECT_EQ(at(-14, -30), report::Agreement::as_predicted);  // the break lies somewhere in (-14, -30]
  EXPECT_EQ(at(-24, -27), report::Agreement::later);
  const auto clean = curve("tilt_triangle", "float", Precision::float32, {step(-1, 100, 0), step(-59, 100, 0)});
  EXPECT_EQ(report::agreement(tilt, clean, verify::find_break(clean), p), report::Agreement::later);
  const auto short_sweep = curve("tilt_triangle", "float", Precision::float32, {step(-1, 100, 0), step(-9, 100, 0)});
  EXPECT_EQ(report::agreement(tilt, short_sweep, verify::find_break(short_sweep), p), report::Agreement::as_predicted);
}

TEST(StabilityText, TableAndSentencesWordForWord) {
  verify::StabilityRun run;
  run.count = 100;
  run.seed = 1;
  run.knobs = {"tilt_triangle", "sliver", "tangency", "magnitude_large", "offset"};
  run.curves = {
      curve("tilt_triangle", "float", Precision::float32, {step(-15, 100, 0, {0}), step(-17, 100, 5, {4})}),
      curve("tilt_triangle", "baldwin-weber", Precision::float32, {step(-13, 100, 0, {0}), step(-15, 100, 8, {0})}),
      curve("tilt_triangle", "certified", Precision::float64, {step(-1, 100, 0, {0}), step(-59, 100, 0, {0})}, exactness()),
      curve("sliver", "float", Precision::float32, {step(0, 100, 0, {1}), step(14, 100, 1, {2})}),
      curve("sliver", "exact", Precision::float64, {step(0, 100, 0), step(40, 100, 0)}, exactness()),
      curve("tangency", "robust", Precision::float32, {step(-21, 100, 0, {0}), step(-24, 100, 3, {0})}),
      curve("magnitude_large", "watertight-float", Precision::float32, {step(16, 100, 0, {0}), step(32, 100, 22, {0})}),
      curve("offset", "float", Precision::float32, {step(16, 200, 0, {0}), step(20, 200, 1, {0})}),
      curve("offset", "baldwin-weber", Precision::float32, {step(4, 200, 0, {9}), step(8, 200, 1, {9})}),
  };
  EXPECT_EQ(report::breaks_table(run),
            "| knob | method | class errors > 0.1% from | median t error > 1 ulp from | predicted class break | measured |\n"
            "|---|---|---|---|---|---|\n"
            "| tilt_triangle | float | 2^-17 | 2^-17 | 2^-16 .. 2^-24 | as predicted |\n"
            "| tilt_triangle | baldwin-weber | 2^-15 | never up to 2^-59 | 2^-16 .. 2^-24 | earlier |\n"
            "| tilt_triangle | certified | never up to 2^-59 | never up to 2^-59 | never in range | as predicted |\n"
            "| sliver | float | 2^14 | 2^14 |  |  |\n"
            "| sliver | exact | never up to 2^40 | never up to 2^40 | never in range | as predicted |\n"
            "| tangency | robust | 2^-24 | never up to 2^-60 | never in range | earlier: past 2^-24 its 24-bit input "
            "cannot hold the gap: R (1 + 2^k) rounds to R, an exact tangent |\n"
            "| magnitude_large | watertight-float | 2^32 | never up to 2^1000 | 2^34 .. 2^43 | earlier: as for a product "
            "of four coordinates (2^24 .. 2^32) |\n"
            "| offset | float | 2^20 | never up to 2^60 | never in range | earlier: past 2^11 its 24-bit input rounds the "
            "case's lattice beside the offset, so it sees a coarser case, not the translated one (1 of 200 cases) |\n"
            "| offset | baldwin-weber | 2^8 | 2^4 | 2^0 .. 2^16 | as predicted |\n");
  const auto s = report::prediction_sentences(run);
  ASSERT_EQ(s.size(), 4u);  // sliver has no derivation: only the exact-class promise
  EXPECT_EQ(s[0],
            "**tilt_triangle** (tilt (|d_z| / max(|d_x|, |d_y|), triangle in a plane with n_z != 0), first class errors "
            "above 0.1%): 24-bit arithmetic: the determinant n . d is 2^k times its terms (up to the normal's slant and "
            "the triangle's shape, typically 2^8 together) and is rounded at 2^-p of them, predicted 2^-16 .. 2^-24; measured float "
            "2^-17 (as predicted), baldwin-weber 2^-15 (earlier); promises the exact class, predicted never in range; "
            "measured certified never up to 2^-59 (as predicted).");
  EXPECT_EQ(s[1],
            "**tangency** (distance from tangency / radius, first class errors above 0.1%): 24-bit arithmetic, "
            "discriminant from the perpendicular vector: exact on these axis-aligned rays, predicted never in range; "
            "measured robust 2^-24 (earlier: past 2^-24 its 24-bit input cannot hold the gap: R (1 + 2^k) rounds to R, "
            "an exact tangent).");
  EXPECT_EQ(s[2],
            "**magnitude_large** (coordinate magnitude, first class errors above 0.1%): 24-bit arithmetic: a product of "
            "three coordinates overflows past 2^128, predicted 2^34 .. 2^43; measured watertight-float 2^32 (earlier: as "
            "for a product of four coordinates (2^24 .. 2^32)).");
  EXPECT_EQ(s[3],
            "**offset** (offset / size, first class errors above 0.1%): 24-bit arithmetic on differences of the inputs: "
            "they are exact at any offset (Sterbenz), predicted never in range; measured float 2^20 (earlier: past 2^11 "
            "its 24-bit input rounds the case's lattice beside the offset, so it sees a coarser case, not the translated "
            "one (1 of 200 cases)); 24-bit arithmetic on absolute positions: an error of 2^-p of the offset reaches the "
            "hits' margin of 2^-8 of the size by an offset of 2^(p-8), predicted 2^0 .. 2^16; measured baldwin-weber 2^8 "
            "(as predicted).");
}

TEST(StabilityReport, SvgHasAPanelPairPerKnobAndNoNaN) {
  verify::StabilityRun run;
  run.count = 10;
  run.seed = 1;
  run.knobs = {"offset", "tangency"};
  run.curves = {
      curve("offset", "float", Precision::float32, {step(0, 10, 0, {0}), step(4, 10, 2, {3}), step(8, 0, 0)}),
      curve("offset", "double", Precision::float64,
            {step(0, 10, 0, {std::numeric_limits<std::uint64_t>::max()}), step(4, 10, 10, {1u << 20})}),
      curve("tangency", "float", Precision::float32, {step(0, 10, 0, {0}), step(-3, 10, 1, {2})}),
  };
  const std::string svg = report::stability_svg(run);
  for (const char* title : {"offset: class error rate", "offset: t error", "tangency: class error rate", "tangency: t error"})
    EXPECT_NE(svg.find(title), std::string::npos) << title;
  // float and double in the legend; offset: 2 methods x (rate + median + max); tangency: 1 x 3.
  EXPECT_NE(svg.find(">float</text>"), std::string::npos);
  EXPECT_NE(svg.find(">double</text>"), std::string::npos);
  const std::regex poly("<polyline points='([^']*)'");
  std::size_t lines = 0;
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), poly); it != std::sregex_iterator(); ++it) {
    ++lines;
    const std::string pts = (*it)[1];
    EXPECT_EQ(pts.find("nan"), std::string::npos) << pts;
    EXPECT_EQ(pts.find("inf"), std::string::npos) << pts;
  }
  EXPECT_EQ(lines, 9u);
}

TEST(StabilityReport, CommandWritesTheStabilityPartOnly) {
  const auto dir = scratch_dir() / "stability_only";
  std::filesystem::remove_all(dir);
  const auto r = run_rayproof("report --stability --stability-count 3 --methods float,double,robust --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "report.md"));
  const std::string md = slurp(dir / "stability.md");
  EXPECT_NE(md.find("## Stability: where each method breaks"), std::string::npos);
  EXPECT_NE(md.find("| tilt_triangle | float |"), std::string::npos);
  EXPECT_NE(md.find("3 cases per step"), std::string::npos);
  const std::string svg = slurp(dir / "stability.svg");
  for (const auto& k : gen::knobs()) EXPECT_NE(svg.find(k.name + ": class error rate"), std::string::npos) << k.name;
  // One row per knob x method x step in the csv.
  std::size_t expect_rows = 0;
  for (const auto& k : gen::knobs()) {
    expect_rows += 3 * k.exponents.size();  // float, double and robust answer every kind
  }
  const std::string csv = slurp(dir / "stability.csv");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), expect_rows + 1);

  // A focused report (--families) gets the stability part only when --stability-count asks for it;
  // then it is appended to report.md as well.
  const auto focused = scratch_dir() / "stability_focused";
  std::filesystem::remove_all(focused);
  auto f = run_rayproof("report --count 4 --families tri_edge --methods float --irradiance-samples 0 --out " + focused.string());
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_FALSE(std::filesystem::exists(focused / "stability.svg"));
  EXPECT_EQ(slurp(focused / "report.md").find("## Stability"), std::string::npos);
  f = run_rayproof("report --count 4 --families tri_edge --methods float --irradiance-samples 0 --stability-count 2 --out " +
                   focused.string());
  ASSERT_EQ(f.status, 0) << f.err;
  EXPECT_TRUE(std::filesystem::exists(focused / "stability.svg"));
  EXPECT_NE(slurp(focused / "report.md").find("## Stability: where each method breaks"), std::string::npos);

  const auto bad = run_rayproof("report --stability --stability-count 0 --out " + dir.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--stability-count"), std::string::npos);
}
