// A user's GLSL functions under the exact test on a Vulkan device (--glsl).
// The wrapper's text and the NoContraction pass without a device; with one (lavapipe in CI): the
// example through `rayproof check`, a compile error's file:line, a shader that never finishes, bad
// files, the device in the output. Skipped, saying why, where no Vulkan device exists.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include "verify/build_compare.h"
#include "cli_support.h"
#include "methods/glsl_kernel.h"
#include "methods/glsl_source.h"
#include "methods/glsl_vulkan.h"

using namespace rayproof;
using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

namespace {

/// The first device's description, or why there is none (then the test skips).
std::variant<std::string, std::string> first_device() {
  static const auto devices = glsl::list_devices();
  if (auto* why = std::get_if<std::string>(&devices)) return std::variant<std::string, std::string>(std::in_place_index<1>, *why);
  return std::variant<std::string, std::string>(std::in_place_index<0>, std::get<0>(devices).front());
}

#define NEED_VULKAN_DEVICE()                                                                 \
  do {                                                                                       \
    const auto dev = first_device();                                                         \
    if (dev.index() == 1) GTEST_SKIP() << "no Vulkan device here: " << std::get<1>(dev);   \
  } while (0)

const std::string kExample = std::string(RAYPROOF_EXAMPLES_DIR) + "/glsl/moller_trumbore.glsl";

io::Case triangle_case(double ox) {
  io::Case c;
  c.kind = io::Kind::triangle;
  // o (ox, 0.25, -1), d (0, 0, 1), triangle (0,0,0) (1,0,0) (0,1,0): a hit at t = 1 for 0 < ox < 0.75.
  c.v = {ox, 0.25, -1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  return c;
}

}  // namespace

TEST(GlslSource, FindsTheKindsDefinedOutsideComments) {
  const auto kinds = glsl::defined_kinds(
      "// int rayproof_box(vec3 o) is not here\n/* rayproof_sphere( */\nint rayproof_triangle (vec3 o) { return "
      "rayproof_plane_x(o); }\nint rayproof_disk(vec3 o);\nint my_rayproof_ellipsoid(vec3 o);\n");
  EXPECT_EQ(kinds, (std::vector<io::Kind>{io::Kind::triangle, io::Kind::disk}));
  EXPECT_TRUE(glsl::legacy_kinds("int rayproof_disk(vec3 o);\n").empty());
  EXPECT_EQ(glsl::legacy_names_warning("f.glsl", "int rayproof_disk(vec3 o);\n"), "");
}

// The old GLSL spelling (rp_KIND, RP_*, rp_real, rp_vec*) works for one release, with a message that
// names what to rename; a file with both spellings of a kind is called by the new one.
TEST(GlslSource, OldNamesStillWorkWithADeprecationMessage) {
  const std::string old_text = "int rp_sphere(rp_vec3 o, rp_vec3 d, rp_vec3 c, rp_real r, out rp_real t) { return RP_MISS; }\n"
                               "int rayproof_box(vec3 o) { return 0; }\n";
  EXPECT_EQ(glsl::defined_kinds(old_text), (std::vector<io::Kind>{io::Kind::sphere, io::Kind::box}));
  EXPECT_EQ(glsl::legacy_kinds(old_text), (std::vector<io::Kind>{io::Kind::sphere}));
  const std::string w = glsl::wrap(old_text, "old.glsl", io::Kind::sphere, Precision::float32);
  EXPECT_NE(w.find("int code = rp_sphere(o, d, rayproof_center, rayproof_radius, t)"), std::string::npos) << w;
  EXPECT_NE(w.find("#define rp_vec3 rayproof_real3"), std::string::npos);
  EXPECT_NE(w.find("#define RP_HIT_T_B 3"), std::string::npos);
  const std::string msg = glsl::legacy_names_warning("old.glsl", old_text);
  EXPECT_NE(msg.find("old.glsl: rp_sphere is the old GLSL spelling; rename it rayproof_sphere"), std::string::npos) << msg;
  EXPECT_NE(msg.find("removed in the next"), std::string::npos) << msg;
  const std::string both = "int rp_sphere(vec3 o) { return 0; }\nint rayproof_sphere(vec3 o) { return 0; }\n";
  EXPECT_TRUE(glsl::legacy_kinds(both).empty());
  EXPECT_NE(glsl::wrap(both, "b.glsl", io::Kind::sphere, Precision::float32).find("int code = rayproof_sphere("), std::string::npos);
}

TEST(GlslSource, KeepsTheUsersLineNumbersAndDropsItsVersion) {
  EXPECT_EQ(glsl::prepare_user_text("  #version 450 core\nint a;\n# version 460\nint b;"), "\nint a;\n\nint b;");
  const std::string w = glsl::wrap("int rayproof_sphere() {}\n", "my file.glsl", io::Kind::sphere, Precision::float64);
  EXPECT_NE(w.find("#line 1 \"my file.glsl\"\nint rayproof_sphere() {}\n"), std::string::npos);
  EXPECT_NE(w.find("#define rayproof_real double"), std::string::npos);
  EXPECT_NE(w.find("#define RAYPROOF_REAL_IS_DOUBLE 1"), std::string::npos);
  EXPECT_NE(w.find("rayproof_sphere(o, d, rayproof_center, rayproof_radius, t)"), std::string::npos);
  EXPECT_EQ(glsl::signature(io::Kind::triangle, Precision::float32),
            "int rayproof_triangle(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, out float t, out vec2 b)");
}

TEST(GlslSource, NoContractionDecoratesEveryFloatOperation) {
  // A hand-made module: header, OpDecorate %1 Binding, OpFMul %t %10 %a %b, OpFAdd %t %11 %10 %c, OpIAdd.
  const std::vector<std::uint32_t> spv{0x07230203, 0x10300, 0, 20, 0,       (4u << 16) | 71, 1, 33, 0,
                                       (5u << 16) | 133,   2, 10, 3, 4,     (5u << 16) | 129, 2, 11, 10, 5,
                                       (5u << 16) | 128,   2, 12, 3, 4};
  const auto out = glsl::decorate_no_contraction(spv);
  ASSERT_EQ(out.size(), spv.size() + 6);
  const std::vector<std::uint32_t> added(out.begin() + 5, out.begin() + 11);
  EXPECT_EQ(added, (std::vector<std::uint32_t>{(3u << 16) | 71, 10, 42, (3u << 16) | 71, 11, 42}));
  EXPECT_TRUE(glsl::decorate_no_contraction({1, 2, 3}).empty());
}

// The example through the CLI in one command, against exact: the naive test's false misses on
// edges are found (so the promise watertight is broken: status 1), the generic family agrees, and
// the output names the device (run time ~1 s on lavapipe).
TEST(Glsl, ExampleCheckedAgainstExactThroughTheCli) {
  NEED_VULKAN_DEVICE();
  const auto r = run_rayproof("check --glsl mt=" + kExample +
                              " --families tri_generic,tri_edge --count 400 --expect watertight --json");
  ASSERT_EQ(r.status, 1) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "mt");
  EXPECT_EQ(j["precision"], "float");
  const std::string dev = std::get<0>(first_device());
  const std::string name = dev.substr(dev.find(": ") + 2, dev.find(" (") - dev.find(": ") - 2);
  EXPECT_NE(j["kernel"].get<std::string>().find(name), std::string::npos) << j["kernel"] << " vs " << dev;
  EXPECT_NE(j["kernel"].get<std::string>().find("driver "), std::string::npos) << j["kernel"];
  ASSERT_EQ(j["families"].size(), 2u);
  const auto& generic = j["families"][0];
  const auto& edge = j["families"][1];
  EXPECT_EQ(generic["family"], "tri_generic");
  EXPECT_EQ(generic["cases"], 400);
  EXPECT_EQ(generic["false_hit"].get<int>() + generic["false_miss"].get<int>(), 0);
  EXPECT_EQ(generic["failures"], 0);
  EXPECT_GT(edge["false_miss"].get<int>(), 0);
  EXPECT_EQ(edge["failures"], 0);
  EXPECT_FALSE(j["promises_kept"].get<bool>());
  // The text output names the device too.
  const auto t = run_rayproof("check --glsl mt=" + kExample + " --families tri_generic --count 100");
  EXPECT_EQ(t.status, 0) << t.err;
  EXPECT_NE(t.out.find("kernel 'mt': GLSL shader " + kExample + " (float) on " + name), std::string::npos) << t.out;
}

// A shader written with the old GLSL names runs as before, with the deprecation message on standard
// error: the same answers as the same formula under the new names.
TEST(Glsl, OldNamesRunWithADeprecationMessage) {
  NEED_VULKAN_DEVICE();
  // One formula; `@` stands for the macros' prefix.
  const std::string body = "(vec3 o, vec3 d, vec3 center, float radius, out float t) {\n"
                           "  vec3 oc = o - center; float b = dot(oc, d), a = dot(d, d);\n"
                           "  float disc = b * b - a * (dot(oc, oc) - radius * radius);\n"
                           "  if (disc < 0.0) return @MISS;\n  t = (-b - sqrt(disc)) / a;\n  return t >= 0.0 ? @HIT_T : @MISS;\n}\n";
  auto spelled = [&](const std::string& fn, const std::string& prefix) {
    std::string text = "int " + fn + body;
    for (std::size_t at; (at = text.find('@')) != std::string::npos;) text.replace(at, 1, prefix);
    return text;
  };
  const auto old_file = write_file("old_names.glsl", spelled("rp_sphere", "RP_"));
  const auto new_file = write_file("new_names.glsl", spelled("rayproof_sphere", "RAYPROOF_"));
  const auto o = run_rayproof("check --glsl s=" + old_file.string() + " --families sph_generic --count 60");
  const auto n = run_rayproof("check --glsl s=" + new_file.string() + " --families sph_generic --count 60");
  EXPECT_NE(o.err.find("rp_sphere is the old GLSL spelling; rename it rayproof_sphere"), std::string::npos) << o.err;
  EXPECT_EQ(n.err.find("old GLSL spelling"), std::string::npos) << n.err;
  EXPECT_EQ(o.status, n.status) << o.err;
  auto table = [](const std::string& out) { return out.substr(std::min(out.size(), out.find("\nfamily "))); };
  ASSERT_NE(table(n.out), "") << n.out;
  EXPECT_EQ(table(o.out), table(n.out));
}

// A compile error names the user's file and line, not the wrapper's (needs no device).
TEST(Glsl, CompileErrorNamesTheUsersFileAndLine) {
  const auto f = write_file("syntax.glsl", "// line 1\nint rayproof_triangle(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, "
                                           "out float t, out vec2 b) {\n  float x = 1.0\n  return RAYPROOF_MISS;\n}\n");
  const auto r = run_rayproof("check --glsl bad=" + f.string() + " --count 10");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(f.string() + ":4: "), std::string::npos) << r.err;  // glslang reports the line it stopped on
  EXPECT_EQ(r.err.find("rayproof wrapper"), std::string::npos) << r.err;
  // A function whose signature is not the documented one: the compiler points into the wrapper,
  // rayproof says which signature it calls.
  const auto g = write_file("signature.glsl", "int rayproof_sphere(vec3 o, vec3 d, float radius, out float t) { return 0; }\n");
  const auto s = run_rayproof("check --glsl bad=" + g.string() + " --count 10");
  EXPECT_EQ(s.status, 2);
  EXPECT_NE(s.err.find("rayproof calls int rayproof_sphere(vec3 o, vec3 d, vec3 center, float radius, out float t)"),
            std::string::npos) << s.err;
}

// Files that are not shaders of ours: a clear message each, status 2 (needs no device).
TEST(Glsl, BadFilesGetAClearMessage) {
  const auto none = write_file("none.glsl", "float helper(float x) { return x; }\n");
  auto r = run_rayproof("check --glsl x=" + none.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("defines none of the functions rayproof calls (rayproof_plane"), std::string::npos) << r.err;
  r = run_rayproof("check --glsl x=/nonexistent/file.glsl");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/nonexistent/file.glsl: no such file"), std::string::npos) << r.err;
  r = run_rayproof("check --glsl x:half=" + kExample);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown precision 'half'"), std::string::npos) << r.err;
  const auto binary = write_file("binary.glsl", std::string("int rayproof_box(\0\x01\x02", 20));
  r = run_rayproof("check --glsl x=" + binary.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not a GLSL text file"), std::string::npos) << r.err;
}

// No Vulkan driver (the loader pointed at none): the message names the Debian packages (needs no device).
TEST(Glsl, NoDeviceNamesTheDebianPackages) {
  const auto r = run_rayproof("check --glsl mt=" + kExample, "",
                              "VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json ");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no Vulkan device: install a Vulkan driver (on Debian: mesa-vulkan-drivers"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("libvulkan"), std::string::npos) << r.err;
}

// A device index that does not exist: the message lists the devices.
TEST(Glsl, UnknownDeviceListsTheDevices) {
  NEED_VULKAN_DEVICE();
  const auto r = run_rayproof("check --glsl mt=" + kExample + " --device 999");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--device 999: there is no such Vulkan device; the devices here:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("  " + std::get<0>(first_device())), std::string::npos) << r.err;
}

// A shader that never finishes on some case: its batch times out, each of its cases is a reported
// failure, and the next batch runs in a new process (run time ~4 s: the shader compiles twice, ~1.5 s each; a 0.5 s timeout).
TEST(Glsl, InfiniteLoopTimesOutAndTheRunGoesOn) {
  NEED_VULKAN_DEVICE();
  // llvmpipe ends a shader's loops after 65535 iterations in all, so a plain `while (true)` finishes
  // there with a wrong answer; this one runs 65535 x 8192 xorshift steps for o.x > 100: 1.9 s on lavapipe
  // here at load 4 (2048 steps took under 0.5 s on a quiet machine and missed the 0.5 s timeout).
  const auto f = write_file("loop.glsl",
                            "#define S n ^= n << 13u; n ^= n >> 17u; n ^= n << 5u;\n"
                            "#define S8 S S S S S S S S\n#define S64 S8 S8 S8 S8 S8 S8 S8 S8\n"
                            "#define S512 S64 S64 S64 S64 S64 S64 S64 S64\n#define S4K S512 S512 S512 S512 S512 S512 S512 S512\n"
                            "int rayproof_triangle(vec3 o, vec3 d, vec3 p0, vec3 p1, vec3 p2, out float t, out vec2 b) {\n"
                            "  uint n = 1u;\n"
                            "  while (o.x > 100.0) { S4K S4K if (n == 0u) break; }\n"
                            "  t = 1.0;\n  b = vec2(float(n));\n  return RAYPROOF_HIT_T;\n}\n");
  GlslOptions opt;
  opt.host = RAYPROOF_BIN;
  opt.timeout_seconds = 0.5;
  auto made = make_glsl_method("loop=" + f.string(), opt);
  ASSERT_TRUE(std::holds_alternative<Method>(made)) << std::get<std::string>(made);
  const Method& m = std::get<Method>(made);
  ASSERT_TRUE(m.take_failures);
  std::vector<io::Case> good{triangle_case(0.25), triangle_case(0.5)};
  std::vector<io::Case> bad{triangle_case(0.25), triangle_case(200), triangle_case(0.5)};
  std::vector<io::CaseResult> out(3);
  m.classify_many(good, std::span(out).first(2));
  EXPECT_EQ(out[0].contact, Contact::hit);
  EXPECT_EQ(out[0].t, 1.0);
  for (const auto& kf : m.take_failures()) ADD_FAILURE() << kf.what;
  m.classify_many(bad, out);
  const auto failures = m.take_failures();
  ASSERT_EQ(failures.size(), 3u);  // the whole dispatch: one invocation per case, none answered
  for (const auto& r : out) EXPECT_EQ(r.contact, Contact::error);
  EXPECT_NE(failures[1].what.find("timed out: no answer within 0.5 s for a dispatch of 3 cases"), std::string::npos)
      << failures[1].what;
  EXPECT_EQ(failures[1].input.v[0], 200);
  out.assign(2, {});
  m.classify_many(good, std::span(out).first(2));  // a new process answers
  EXPECT_EQ(out[1].contact, Contact::hit);
  EXPECT_EQ(out[1].t, 1.0);
  EXPECT_TRUE(m.take_failures().empty());
}

// The GPU build against the C build: each difference sorted by cause, the sentences from known tallies.
TEST(BuildCompare, SortsDifferencesByCauseAndSaysSo) {
  auto answer = [](double t) {
    io::CaseResult r;
    r.form = io::AnswerForm::coarse;
    r.contact = Contact::hit;
    r.t = t;
    return r;
  };
  // Case i: o.x = i (case 3 has a subnormal float input). The C build answers t = 1 everywhere; the
  // GPU build differs on cases 1, 2, 3; its precise variant agrees with C on case 1 only.
  auto make = [&](const char* name, std::function<double(const io::Case&)> t) {
    Method m;
    m.name = name;
    m.precision = Precision::float32;
    m.kinds = {io::Kind::triangle};
    m.classify = [t, answer](const io::Case& c) { return answer(t(c)); };
    return m;
  };
  const Method c = make("c", [](const io::Case&) { return 1.0; });
  const Method gpu = make("gpu", [](const io::Case& x) { return x.v[1] == 0 ? 1.0 : 1.5; });
  const Method precise = make("precise", [](const io::Case& x) { return x.v[1] == 1 ? 1.0 : 2.0; });
  std::vector<io::Case> cases;
  for (int i = 0; i < 5; ++i) {
    io::Case k = triangle_case(0.25);
    k.v[1] = i == 4 ? 0 : i;
    if (i == 3) k.v[2] = 1e-40;  // a float subnormal
    cases.push_back(k);
  }
  auto r = verify::compare_builds(verify::DeviceLanguage::glsl, gpu, c, &precise, cases, 10);
  EXPECT_EQ(r.cases, 5u);
  EXPECT_EQ(r.differ, 3u);
  EXPECT_EQ(r.differ_hit, 0u);
  EXPECT_EQ(r.contraction, 1u);
  EXPECT_EQ(r.subnormal, 1u);
  EXPECT_EQ(r.unexplained, 1u);
  EXPECT_EQ(r.uncontracted_differ, 4u);  // the precise build agrees with C on case 1 only
  ASSERT_EQ(r.examples.size(), 3u);
  EXPECT_EQ(r.examples[0].why, "contraction");
  EXPECT_EQ(r.examples[1].why, "unexplained");
  EXPECT_EQ(r.examples[2].why, "subnormal");
  r.device_note = "subnormal floats: may be flushed";
  auto lines = verify::comparison_lines(r);
  ASSERT_GE(lines.size(), 8u);
  EXPECT_EQ(lines[1].rfind("speed on these 5 cases, one pass each, side by side: 'gpu' ", 0), 0u) << lines[1];
  lines.erase(lines.begin() + 1);
  EXPECT_EQ(lines[1], "'gpu' and 'c' answer differently on 3 of 5 cases (60.00%), 0 of them hit against miss:");
  EXPECT_EQ(lines[2].rfind("  1 of them agree with the C build with every float operation of the shader precise", 0), 0u)
      << lines[2];
  EXPECT_NE(lines[3].find("  1 of them involve a value in the subnormal range"), std::string::npos);
  EXPECT_NE(lines[3].find("the device: subnormal floats: may be flushed"), std::string::npos);
  EXPECT_EQ(lines[4], "  1 of them: neither cause shows.");
  EXPECT_EQ(lines[5], "The build without contraction ('precise') differs from the C build on 4 cases.");
  EXPECT_EQ(lines[6].rfind("# the first 3:", 0), 0u) << lines[6];
  const auto same = verify::compare_builds(verify::DeviceLanguage::glsl, c, c, nullptr, cases, 10);
  auto timed = same;
  timed.device_seconds = 0.5, timed.c_seconds = 0.001;
  EXPECT_EQ(verify::comparison_lines(timed)[1],
            "speed on these 5 cases, one pass each, side by side: 'c' 0.00 M cases/s (batches through the device, "
            "copies and pipes included), 'c' 0.01 M cases/s (one thread)");
  EXPECT_EQ(verify::comparison_lines(same)[2],
            "'c' and 'c' give the same answer (class, t and barycentrics, bit for bit) on all 5 cases.");
}

// The example against its C build through the CLI: the comparison's counts add up and its sentence
// agrees with them, whatever the device (run time ~2 s).
TEST(Glsl, ExampleAgainstItsCBuildThroughTheCli) {
  NEED_VULKAN_DEVICE();
  const auto r = run_rayproof("check --glsl mt=" + kExample + " --compare-plugin " + PLUGIN_MT_FLOAT +
                              " --families tri_edge,tri_near_parallel --count 200 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out)["compare_plugin"];
  EXPECT_EQ(j["c"], "mt-float-c");
  EXPECT_EQ(j["cases"], 400);
  EXPECT_EQ(j["differ"].get<int>(), j["contraction"].get<int>() + j["subnormal"].get<int>() + j["unexplained"].get<int>());
  const auto t = run_rayproof("check --glsl mt=" + kExample + " --compare-plugin " + PLUGIN_MT_FLOAT +
                              " --families tri_edge,tri_near_parallel --count 200");
  ASSERT_EQ(t.status, 0) << t.err;
  const std::string want = j["differ"] == 0
      ? "'mt' and 'mt-float-c' give the same answer (class, t and barycentrics, bit for bit) on all 400 cases."
      : fmt::format("'mt' and 'mt-float-c' answer differently on {} of 400 cases", j["differ"].get<int>());
  EXPECT_NE(t.out.find(want), std::string::npos) << t.out;
  // A double C build against a float shader: refused.
  const auto d = run_rayproof("check --glsl mt=" + kExample + " --compare-plugin " + PLUGIN_MT_C + " --count 10");
  EXPECT_EQ(d.status, 2);
  EXPECT_NE(d.err.find("a double plugin, the kernel is float"), std::string::npos) << d.err;
}
