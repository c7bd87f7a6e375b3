// --opencl NAME=FILE through the CLI (docs/opencl.md): the example checked against exact on an
// OpenCL device, a build error with the user's file and line, a kernel that loops forever timing
// out while the run goes on, a bad FILE, no device. Needs an OpenCL device (pocl in CI); the tests
// that need one skip with a message where there is none. pocl's kernel cache is a fresh directory
// of each test process (POCL_CACHE_DIR), so nothing is compiled ahead of the test; only the loop
// test's restart, which builds the same program again, finds it there.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

const std::string kNoCache =
    "POCL_CACHE_DIR=" + (rayproof::testing::scratch_dir() / "pocl_cache").string() + " ";

/// The first device's line of `rayproof opencl-host --list`, or empty when there is no device.
std::string first_device() {
  static const std::string dev = [] {
    const auto r = run_rayproof("opencl-host --list", "", kNoCache);
    if (r.status != 0) return std::string();
    const auto colon = r.out.find(": ");
    const auto paren = r.out.find(" (");
    if (colon == std::string::npos || paren == std::string::npos) return std::string();
    return r.out.substr(colon + 2, paren - colon - 2);
  }();
  return dev;
}

#define REQUIRE_OPENCL_DEVICE()                                                                    \
  if (first_device().empty())                                                                      \
  GTEST_SKIP() << "no OpenCL device (rayproof opencl-host --list found none; on Debian: apt-get "  \
                  "install ocl-icd-opencl-dev pocl-opencl-icd)"

const std::string kExample = std::string(RAYPROOF_EXAMPLES_DIR) + "/opencl/moller_trumbore.cl";

/// The check table's row of a family: its numbers, in the table's order.
std::vector<long> row(const std::string& out, const std::string& family) {
  std::vector<long> v;
  const auto at = out.find("\n" + family + " ");
  if (at == std::string::npos) return v;
  std::istringstream line(out.substr(at + 1 + family.size(), out.find('\n', at + 1) - at - 1 - family.size()));
  for (std::string w; line >> w;) v.push_back(w == "-" ? -1 : std::atol(w.c_str()));
  return v;
}

TEST(OpenclCli, ExampleCheckedAgainstExactNamesTheDevice) {
  REQUIRE_OPENCL_DEVICE();
  const auto r = run_rayproof("check --opencl mt-cl=" + kExample + " --families tri_edge,tri_generic --count 400 "
                              "--expect watertight", "", kNoCache);
  // The naive Möller–Trumbore misses rays through edges: the promise is broken (status 1).
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("kernel 'mt-cl': OpenCL C"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(first_device()), std::string::npos) << "the device is named: " << r.out;
  EXPECT_NE(r.out.find("driver "), std::string::npos) << r.out;
  const auto edge = row(r.out, "tri_edge"), generic = row(r.out, "tri_generic");
  ASSERT_GE(edge.size(), 3u) << r.out;
  ASSERT_GE(generic.size(), 3u) << r.out;
  EXPECT_EQ(edge[0], 400);
  EXPECT_GT(edge[2], 0) << "false misses on edges: " << r.out;
  EXPECT_EQ(generic[0], 400);
  EXPECT_EQ(generic[1] + generic[2] + generic[3], 0) << "no class error on generic triangles: " << r.out;
  EXPECT_EQ(generic.back(), 0) << "no kernel failure: " << r.out;
  EXPECT_NE(r.out.find("Promise watertight: BROKEN"), std::string::npos) << r.out;
}

TEST(OpenclCli, CompareWithTheCBuildFindsFmaContraction) {
  REQUIRE_OPENCL_DEVICE();
  // The written-out formula differs from its C build only where the device contracts a * b + c into
  // an FMA; a device without FMA (CL_FP_FMA) could agree everywhere, so only the sentence is fixed.
  const auto r = run_rayproof("check --opencl mt-x=" + std::string(RAYPROOF_EXAMPLES_DIR) +
                                  "/opencl/moller_trumbore_expanded.cl --compare-plugin " PLUGIN_MT_FLOAT_C
                                  " --families tri_generic,tri_edge --count 400",
                              "", kNoCache);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  const auto at = r.out.find("# the device build 'mt-x' against the C build 'mt-c-float'");
  ASSERT_NE(at, std::string::npos) << r.out << r.err;
  const std::string tail = r.out.substr(at);
  EXPECT_NE(tail.find("The build without contraction ('mt-x-contract-off') agrees with the C build on every case."),
            std::string::npos)
      << tail;
  if (tail.find("give the same answer (class, t and barycentrics, bit for bit) on all 800 cases") == std::string::npos) {
    EXPECT_NE(tail.find("of 800 cases"), std::string::npos) << tail;
    EXPECT_NE(tail.find("of them agree with the C build built with `#pragma OPENCL FP_CONTRACT OFF`: the device's "
                        "compiler contracted"),
              std::string::npos)
        << tail;
    EXPECT_NE(tail.find("  0 of them: neither cause shows."), std::string::npos) << tail;
  }
}

TEST(OpenclCli, DoubleWhereTheDeviceHasIt) {
  REQUIRE_OPENCL_DEVICE();
  const auto r = run_rayproof("check --opencl mt:double=" + kExample + " --families tri_generic --count 200 --json", "",
                              kNoCache);
  if (r.status == 2 && r.err.find("has no double precision (cl_khr_fp64)") != std::string::npos)
    GTEST_SKIP() << "the device has no cl_khr_fp64: " << r.err;
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"precision\": \"double\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(".cl (double) on OpenCL device 0"), std::string::npos) << r.out;
  // Double Möller–Trumbore on generic triangles: every class right, t within a few double ulps.
  EXPECT_NE(r.out.find("\"false_miss\": 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"false_hit\": 0"), std::string::npos) << r.out;
  const auto at = r.out.find("\"ulp_median\": ");
  ASSERT_NE(at, std::string::npos) << r.out;
  ASSERT_TRUE(std::isdigit(static_cast<unsigned char>(r.out[at + 14]))) << "a t was compared: " << r.out;
  EXPECT_LE(std::atol(r.out.c_str() + at + 14), 16) << r.out;
}

TEST(OpenclCli, BuildErrorNamesTheUsersFileAndLine) {
  REQUIRE_OPENCL_DEVICE();
  const auto f = write_file("typo.cl",
                            "/* line 1 */\n"
                            "int rayproof_box(rayproof_real3 o, rayproof_real3 d, rayproof_real3 lo, rayproof_real3 hi,\n"
                            "                 rayproof_real* t) {\n"
                            "  return undefined_name + 1;\n"
                            "}\n");
  const auto r = run_rayproof("check --opencl " + f.string(), "", kNoCache);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("typo.cl:4:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("undefined_name"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("rayproof wrapper"), std::string::npos) << "the error is in the user's text: " << r.err;
}

TEST(OpenclCli, KernelThatLoopsForeverTimesOutAndTheRunGoesOn) {
  REQUIRE_OPENCL_DEVICE();
  // The sphere function never returns; the box function (the slab test) answers.
  const auto f = write_file("loops.cl",
                            "int rayproof_sphere(rayproof_real3 o, rayproof_real3 d, rayproof_real3 c, rayproof_real r,\n"
                            "                    rayproof_real* t) {\n"
                            "  volatile int k = 0;\n"
                            "  while (k == 0) { }\n"
                            "  return RAYPROOF_MISS;\n"
                            "}\n"
                            "int rayproof_box(rayproof_real3 o, rayproof_real3 d, rayproof_real3 lo, rayproof_real3 hi,\n"
                            "                 rayproof_real* t) {\n"
                            "  const rayproof_real3 inv = 1 / d, a = (lo - o) * inv, b = (hi - o) * inv;\n"
                            "  const rayproof_real3 n = fmin(a, b), f = fmax(a, b);\n"
                            "  const rayproof_real t0 = fmax(fmax(n.x, n.y), n.z), t1 = fmin(fmin(f.x, f.y), f.z);\n"
                            "  if (!(t0 <= t1) || t1 < 0) return RAYPROOF_MISS;\n"
                            "  *t = t0 >= 0 ? t0 : t1;\n"
                            "  return RAYPROOF_HIT_T;\n"
                            "}\n");
  const auto r = run_rayproof("check --opencl " + f.string() + " --families sph_generic,box_generic --count 40 "
                              "--exec-timeout 0.5", "", kNoCache + "timeout 120 ");
  EXPECT_EQ(r.status, 0) << r.out << r.err;  // no promise stated
  const auto sph = row(r.out, "sph_generic"), box = row(r.out, "box_generic");
  ASSERT_FALSE(sph.empty()) << r.out << r.err;
  ASSERT_FALSE(box.empty()) << r.out << r.err;
  EXPECT_EQ(sph.back(), 40) << "every case of the hung batch is a kernel failure: " << r.out;
  EXPECT_NE(r.out.find("timed out: no answer after 0.5 s"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("OpenCL cannot stop a running kernel"), std::string::npos) << r.out;
  // After the timeout a new device process answered the boxes: no failure, the slab test's answers
  // (pocl: no class error on these 40; a device may differ on a case or two, garbage on half).
  EXPECT_EQ(box[0], 40);
  EXPECT_EQ(box.back(), 0) << r.out;
  EXPECT_LE(box[1] + box[2] + box[3], 4) << r.out;
}

TEST(OpenclCli, BadFileIsAClearMessage) {
  // No device needed: FILE is read before the device process starts.
  auto r = run_rayproof("check --opencl mine=/nonexistent/k.cl");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/nonexistent/k.cl: no such file"), std::string::npos) << r.err;
  const auto none = write_file("none.cl", "/* int rayproof_triangle(...) in a comment only */\nint f(void) { return 0; }\n");
  r = run_rayproof("check --opencl " + none.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("defines none of the functions rayproof_plane"), std::string::npos) << r.err;
  const auto bin = write_file("bin.cl", std::string("int rayproof_box(\0\1\2", 20));
  r = run_rayproof("check --opencl " + bin.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("a binary file"), std::string::npos) << r.err;
  r = run_rayproof("check --opencl m:quad=" + kExample);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("precision 'quad' (float or double)"), std::string::npos) << r.err;
}

TEST(OpenclCli, NoDeviceNamesThePackagesAndABadDeviceListsThem) {
  // No ICD: the loader (ocl-icd) finds no platform.
  auto r = run_rayproof("check --opencl " + kExample, "", "OCL_ICD_VENDORS=/nonexistent-dir ");
  if (r.status == 0 || r.err.find("no OpenCL platform") == std::string::npos)
    if (r.err.find("built without OpenCL") == std::string::npos)
      GTEST_SKIP() << "this ICD loader does not read OCL_ICD_VENDORS (not ocl-icd): " << r.err;
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("ocl-icd-opencl-dev"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pocl-opencl-icd"), std::string::npos) << r.err;
  REQUIRE_OPENCL_DEVICE();
  r = run_rayproof("check --opencl " + kExample + " --device 999", "", kNoCache);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no OpenCL device 999"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("0: " + first_device()), std::string::npos) << r.err;
}

}  // namespace

// The parts that need no device: which kinds a file defines, the wrapper, the answer codes, the
// comparison's sentences from known tallies.
#include "verify/build_compare.h"
#include "methods/opencl_wrapper.h"

namespace {

using namespace rayproof;

TEST(OpenclWrapper, KindsDefinedOutsideComments) {
  const auto k = opencl::kinds_defined("// int rayproof_plane(\n/* rayproof_disk ( */ int rayproof_box (int x);\n"
                                       "int my_rayproof_sphere(void); int rayproof_triangle_x(void);\n"
                                       "int rayproof_triangle\n(void);");
  EXPECT_EQ(k, (std::vector<io::Kind>{io::Kind::triangle, io::Kind::box}));
}

TEST(OpenclWrapper, UserTextFollowsALineDirectiveNamingTheFile) {
  const std::string src = opencl::wrapper_source("int rayproof_sphere(...);", "/a/b \"q\".cl", {io::Kind::sphere},
                                                 opencl::WrapperOptions{Precision::float64, true});
  const auto line = src.find("#line 1 \"/a/b \\\"q\\\".cl\"\nint rayproof_sphere(...);\n");
  EXPECT_NE(line, std::string::npos) << src;
  EXPECT_LT(src.find("cl_khr_fp64 : enable"), line);
  EXPECT_LT(src.find("#pragma OPENCL FP_CONTRACT OFF"), line);
  EXPECT_NE(src.find("typedef double rayproof_real;"), std::string::npos);
  EXPECT_NE(src.find("__kernel void rayproof_run_sphere("), std::string::npos);
  EXPECT_NE(src.find(", v[9], &t);"), std::string::npos) << "the radius is field 9: " << src;
}

TEST(OpenclWrapper, AnswerCodes) {
  auto r = opencl::to_result(io::Kind::triangle, {opencl::kHitTB, 2.0, 0.25, 0.5});
  ASSERT_TRUE(std::holds_alternative<io::CaseResult>(r));
  EXPECT_EQ(std::get<io::CaseResult>(r).contact, Contact::hit);
  EXPECT_EQ(std::get<io::CaseResult>(r).b2, 0.5);
  r = opencl::to_result(io::Kind::box, {opencl::kHitTB, 2.0, 0.25, 0.5});
  EXPECT_TRUE(std::holds_alternative<std::string>(r));
  r = opencl::to_result(io::Kind::box, {7, 0, 0, 0});
  ASSERT_TRUE(std::holds_alternative<std::string>(r));
  EXPECT_NE(std::get<std::string>(r).find("returned 7"), std::string::npos);
  r = opencl::to_result(io::Kind::box, {opencl::kHit, 2.0, 0, 0});
  EXPECT_FALSE(std::get<io::CaseResult>(r).t.has_value());
}

// The OpenCL wording of the one comparison text (verify/build_compare.h), from known tallies.
TEST(OpenclCompare, SentencesFromKnownTallies) {
  verify::BuildComparison c;
  c.language = verify::DeviceLanguage::opencl;
  c.device = "dev", c.c = "c", c.uncontracted = "dev-contract-off";
  c.cases = 4000, c.differ = 1014, c.differ_hit = 225, c.contraction = 1014, c.uncontracted_differ = 0;
  auto s = verify::comparison_lines(c);
  ASSERT_EQ(s.size(), 6u);
  EXPECT_EQ(s[1], "'dev' and 'c' answer differently on 1014 of 4000 cases (25.35%), 225 of them hit against miss:");
  EXPECT_EQ(s[2].rfind("  1014 of them agree with the C build built with `#pragma OPENCL FP_CONTRACT OFF`: the device's "
                       "compiler contracted multiply-adds into FMA", 0), 0u) << s[2];
  EXPECT_EQ(s[3].rfind("  0 of them involve a value in the subnormal range", 0), 0u) << s[3];
  EXPECT_EQ(s[4], "  0 of them: neither cause shows.");
  EXPECT_EQ(s[5], "The build without contraction ('dev-contract-off') agrees with the C build on every case.");
  c.contraction = 14, c.uncontracted_differ = 1000, c.subnormal = 3, c.unexplained = 997;
  c.device_note = "flushes subnormal floats to zero (no CL_FP_DENORM in CL_DEVICE_SINGLE_FP_CONFIG)";
  s = verify::comparison_lines(c);
  ASSERT_EQ(s.size(), 6u);
  EXPECT_EQ(s[2].rfind("  14 of them agree", 0), 0u) << s[2];
  EXPECT_NE(s[3].find("  3 of them involve a value in the subnormal range"), std::string::npos) << s[3];
  EXPECT_NE(s[3].find("the device: flushes subnormal floats to zero"), std::string::npos) << s[3];
  EXPECT_EQ(s[4], "  997 of them: neither cause shows.");
  EXPECT_EQ(s[5], "The build without contraction ('dev-contract-off') differs from the C build on 1000 cases.");
  c = verify::BuildComparison{};
  c.device = "dev", c.c = "c", c.cases = 10;
  s = verify::comparison_lines(c);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1], "'dev' and 'c' give the same answer (class, t and barycentrics, bit for bit) on all 10 cases.");
  c.cases = 0, c.failed = 1;
  s = verify::comparison_lines(c);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[2], "1 case is left out: a failure of either build (reported above).");
  EXPECT_EQ(s[3], "No case was answered by both 'dev' and 'c': nothing to compare.");
}

}  // namespace
