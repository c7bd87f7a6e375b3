// rayproof check: the checker engine (verify/check.h) against verify's own
// judgement, its promises, its batches and kernel failures; the sentences built from known tallies;
// the command's verdicts, exit codes and files; the leak check on closed meshes (verify/mesh_check.h).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "verify/check_text.h"
#include "cli/mesh_check_text.h"
#include "registry/registry.h"
#include "cli_support.h"
#include "report/report_text.h"
#include "verify/check.h"
#include "verify/exact_method.h"
#include "verify/mesh_check.h"
#include "verify/mesh_fuzz.h"
#include "verify/ulp_text.h"

using namespace rayproof;
using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::slurp;

namespace {

const Method& method(const std::string& name) {
  const Method* m = registry::all_methods().find(name);
  EXPECT_NE(m, nullptr) << name;
  return *m;
}

std::vector<const gen::Family*> families(std::initializer_list<const char*> names) {
  std::vector<const gen::Family*> out;
  for (const char* n : names) out.push_back(gen::find_family(n));
  return out;
}

verify::CheckOptions small(std::initializer_list<const char*> names, std::size_t count) {
  verify::CheckOptions o;
  o.families = families(names);
  o.count = count;
  o.seed = 5;
  return o;
}

}  // namespace

TEST(Check, TalliesAreVerifysJudgementOfTheSameCases) {
  const Method& m = method("float");
  auto opt = small({"tri_edge", "tri_vertex", "sph_tangent_exact"}, 120);
  const auto res = verify::check(m, opt);
  ASSERT_EQ(res.families.size(), 3u);
  for (const auto& fc : res.families) {
    std::vector<io::Case> cases;
    for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
      auto part = gen::generate(*gen::find_family(fc.family), 60, 5, p);
      cases.insert(cases.end(), part.begin(), part.end());
    }
    const auto cmp = verify::compare(cases, verify::exact_answers(cases), {&m}, 0);
    const auto& want = cmp.stats.at({"float", fc.family});
    EXPECT_EQ(fc.stats.cases, want.cases) << fc.family;
    EXPECT_EQ(fc.stats.false_hit, want.false_hit) << fc.family;
    EXPECT_EQ(fc.stats.false_miss, want.false_miss) << fc.family;
    EXPECT_EQ(fc.stats.wrong_hit_class, want.wrong_hit_class) << fc.family;
    EXPECT_EQ(fc.stats.wrong_class, want.wrong_class) << fc.family;
    EXPECT_EQ(fc.stats.ulps, want.ulps) << fc.family;
  }
  // The naive float Möller–Trumbore loses exact edge and vertex hits.
  EXPECT_GT(res.families[0].stats.false_miss + res.families[1].stats.false_miss, 0u);
}

TEST(Check, FloatBreaksWatertightAndCertifiedKeepsEverything) {
  auto opt = small({"tri_edge", "tri_vertex"}, 200);
  opt.promises.watertight = true;
  const auto f = verify::check(method("float"), opt);
  ASSERT_EQ(f.promises.size(), 1u);
  EXPECT_FALSE(f.promises[0].kept);
  EXPECT_EQ(f.promises[0].violations, f.families[0].stats.false_miss + f.families[1].stats.false_miss);
  EXPECT_FALSE(f.promises_kept());
  // Reproducers: class errors come first, and each one still fails on the kernel.
  for (const auto& fc : f.families) {
    ASSERT_FALSE(fc.worst.empty()) << fc.family;
    EXPECT_NE(fc.worst.front().judged.verdict, verify::Verdict::agree) << fc.family;
    for (const auto& w : fc.worst) {
      const auto again = method("float").run(w.judged.input);
      EXPECT_EQ(again, w.judged.got) << io::format_case(w.judged.input);
    }
  }

  verify::CheckOptions all;  // every family of the kinds certified answers
  all.count = 24;
  all.seed = 3;
  all.promises = {true, true, 1};
  const auto c = verify::check(method("certified"), all);
  EXPECT_EQ(c.families.size(), gen::families().size());
  EXPECT_EQ(c.total().class_errors(), 0u);
  EXPECT_EQ(c.over_tolerance(), 0u);
  EXPECT_TRUE(c.promises_kept());
  EXPECT_EQ(c.promises.size(), 3u);
}

TEST(Check, UsesBatchesAndCountsKernelFailures) {
  // A kernel that answers only through batches (as --exec and --plugin do) and "fails" on every
  // case whose first number is negative, reporting it through take_failures.
  const Method& robust = method("robust");
  Method k;
  k.name = "batchy";
  k.precision = robust.precision;
  k.kinds = {io::Kind::triangle};
  auto batches = std::make_shared<std::size_t>(0);
  auto failed = std::make_shared<std::vector<KernelFailure>>();
  k.classify = [](const io::Case&) -> io::CaseResult { ADD_FAILURE() << "classify called instead of a batch"; return {}; };
  k.classify_batch = [&robust, batches, failed](std::span<const io::Case> in, std::span<io::CaseResult> out) {
    ++*batches;
    for (std::size_t i = 0; i < in.size(); ++i) {
      out[i] = robust.classify(in[i]);
      if (in[i].v[0] < 0) out[i] = {Contact::error}, failed->push_back({"crashed (signal 11)", in[i]});
    }
  };
  k.take_failures = [failed] { return std::exchange(*failed, {}); };
  auto opt = small({"tri_generic"}, 100);
  opt.batch = 16;
  opt.minimize = false;  // minimizing calls classify case by case
  opt.promises.exact_class = true;
  const auto res = verify::check(k, opt);
  EXPECT_EQ(*batches, 7u);  // ceil(100 / 16)
  std::size_t negative = 0;
  for (auto p : {gen::Precision::float32, gen::Precision::float64})
    for (const auto& c : gen::generate(*gen::find_family("tri_generic"), 50, 5, p)) negative += float(c.v[0]) < 0;
  ASSERT_GT(negative, 0u);
  EXPECT_EQ(res.failures(), negative);
  ASSERT_EQ(res.promises.size(), 1u);
  EXPECT_FALSE(res.promises[0].kept);
  EXPECT_GE(res.promises[0].violations, negative);
}

TEST(Check, CallableOverloadChecksACppKernel) {
  const Method& d = method("double");
  auto opt = small({"plane_exact"}, 40);
  const auto res = verify::check([&d](const io::Case& c) { return d.classify(c); }, Precision::float64,
                                 {io::Kind::plane}, opt, "mine");
  const auto ref = verify::check(d, opt);
  EXPECT_EQ(res.method, "mine");
  EXPECT_EQ(res.families[0].stats.ulps, ref.families[0].stats.ulps);
  EXPECT_EQ(res.families[0].stats.class_errors(), ref.families[0].stats.class_errors());
}

// One wording of t errors in check (the command and Python's table, which is this
// function's) and report: no raw 19-digit ulp count.
TEST(CheckText, TErrorsAreWordedAsReportWordsThem) {
  verify::CheckResult r;
  r.precision = Precision::float64;
  verify::FamilyCheck a;
  a.family = "tri_generic";
  a.stats.cases = 100;
  a.stats.ulps.assign(96, 3);
  a.stats.ulps.insert(a.stats.ulps.end(), {4527287023342080819ULL, 4527287023342080819ULL, 4527287023342080819ULL,
                                           verify::kNaNUlps});
  r.families = {a};
  const std::string table = verify::check_table(r);
  EXPECT_NE(table.find(" 4.5e+18 (leading bits wrong) "), std::string::npos) << table;  // p99
  EXPECT_NE(table.find(" NaN t "), std::string::npos) << table;
  EXPECT_EQ(table.find("4527287023342080819"), std::string::npos) << table;
  // The same words as report's tables, number for number and in both precisions.
  const std::vector<std::uint64_t> samples{0, 999999, 1000000, std::uint64_t{1} << 23, std::uint64_t{1} << 52,
                                           4527287023342080819ULL, verify::kNaNUlps};
  for (const std::uint64_t u : samples)
    for (const Precision p : {Precision::float32, Precision::float64})
      EXPECT_EQ(verify::ulp_text(u, p), report::ulp_text(u, p)) << u;
  EXPECT_EQ(verify::ulp_text(3, Precision::float64), "3");
  EXPECT_EQ(verify::ulp_text(std::uint64_t{1} << 23, Precision::float32), "8.4e+06 (leading bits wrong)");
  EXPECT_EQ(verify::ulp_text(std::uint64_t{1} << 23, Precision::float64), "8.4e+06 (rel. <= 2e-09)");
  // Every line of the table as wide as the header: the widened columns stay aligned.
  const auto first = table.find('\n');
  for (std::size_t at = 0; at < table.size();) {
    const auto end = table.find('\n', at);
    EXPECT_EQ(end - at, first) << table;
    at = end + 1;
  }
  r.families[0].worst.push_back({"tri_generic", {}, false});
  r.families[0].worst[0].judged.verdict = verify::Verdict::agree;
  r.families[0].worst[0].judged.ulps = 4527287023342080819ULL;
  const auto lines = verify::reproducer_lines(r);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("(4.5e+18 (leading bits wrong) ulps)"), std::string::npos) << lines[0];
}

TEST(CheckText, SentencesStateTheTalliesBesideThem) {
  verify::CheckResult r;
  r.ulp_tolerance = 2;
  verify::FamilyCheck a;
  a.family = "tri_edge";
  a.stats.cases = 200;
  a.stats.false_hit = 1, a.stats.false_miss = 7, a.stats.wrong_hit_class = 2, a.stats.wrong_class = 0;
  a.stats.ulps = {0, 1, 3, 9, 2};
  a.over_tolerance = 2;
  verify::FamilyCheck b;
  b.family = "sph_generic";
  b.stats.cases = 100;
  b.stats.ulps = {0, 0, 1};
  b.failures.push_back({"timed out after 5 s", {}});
  r.families = {a, b};
  r.promises = {{"watertight", false, 8}, {"max-ulps 2", false, 2}};
  const auto s = verify::check_sentences(r);
  ASSERT_EQ(s.size(), 6u);
  EXPECT_EQ(s[0], "10 of 300 cases (3.33%) have a class error: 1 false hit, 7 false misses, 2 wrong classes.");
  EXPECT_EQ(s[1], "2 of the 8 class-correct cases that carry a t (25%) are more than 2 ulps off (largest: 9).");
  EXPECT_EQ(s[2], "The kernel failed (crashed, hung or answered unreadably) on 1 case.");
  EXPECT_EQ(s[3], "Promise watertight: BROKEN by 8 cases (false misses and failures on tri_edge and tri_vertex).");
  EXPECT_EQ(s[4], "Promise max-ulps 2: BROKEN by 2 cases with a t further off.");
  EXPECT_EQ(s[5], "2 of 2 stated promises are broken.");

  r.families = {b};
  r.families[0].failures.clear();
  r.ulp_tolerance = 1;
  r.promises = {{"exact-class", true, 0}};
  const auto k = verify::check_sentences(r);
  ASSERT_EQ(k.size(), 4u);
  EXPECT_EQ(k[0], "No class error in 100 cases.");
  EXPECT_EQ(k[1], "Every t of the 3 class-correct cases that carry one is within 1 ulp of exact (largest: 1).");
  EXPECT_EQ(k[2], "Promise exact-class: kept (no class error and no failure on any family).");
  EXPECT_EQ(k[3], "The stated promise is kept.");

  std::vector<verify::MeshCheck> m(2);
  m[0].mesh = "a.off", m[0].rays = 100, m[0].leaks = 4, m[0].rays_without_candidates = 20;
  m[1].mesh = "b.off", m[1].rays = 50;
  const auto ms = cli::mesh_sentences(m);
  ASSERT_EQ(ms.size(), 3u);
  EXPECT_EQ(ms[0], "4 of 130 rays with candidates (3.08%) leaked: the kernel hit none of their candidate triangles; "
                   "1 of 2 meshes leaked.");
  EXPECT_EQ(ms[1], "20 rays found no candidate triangle (not charged to the kernel).");
  EXPECT_EQ(ms[2], "Promise watertight: BROKEN by 4 leaks and 0 failures.");
}

TEST(CheckCli, CertifiedPassesAndFloatFailsWatertight) {
  auto c = run_rayproof("check --method certified --count 20 --seed 2 --expect exact-class --max-ulps 1");
  EXPECT_EQ(c.status, 0) << c.out << c.err;
  EXPECT_NE(c.out.find("All 2 stated promises are kept."), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("No class error in "), std::string::npos) << c.out;

  auto f = run_rayproof("check --method float --count 100 --seed 2 --families tri_edge,tri_vertex --expect watertight");
  EXPECT_EQ(f.status, 1) << f.out << f.err;
  EXPECT_NE(f.out.find("Promise watertight: BROKEN by "), std::string::npos) << f.out;
  EXPECT_NE(f.out.find("false-miss, got "), std::string::npos) << f.out;  // a reproducer line
  // A reproducer line is a case line that classify reads back.
  const auto line = f.out.substr(f.out.find("\ntriangle ") + 1);
  auto again = run_rayproof("classify --method float -", line.substr(0, line.find('\n')) + "\n");
  EXPECT_EQ(again.status, 0) << again.err;
  EXPECT_EQ(again.out.rfind("miss", 0) == 0 || again.out.rfind("behind", 0) == 0, true) << again.out;

  // Without a stated promise, the same run succeeds: findings are not failures.
  EXPECT_EQ(run_rayproof("check --method float --count 20 --families tri_edge").status, 0);
}

TEST(CheckCli, JsonAgreesWithTheTable) {
  auto r = run_rayproof("check --method float --count 60 --seed 4 --families tri_edge,sph_generic --json --max-ulps 4");
  ASSERT_EQ(r.status, 1) << r.err;  // float's t is not within 4 ulps everywhere
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "float");
  ASSERT_EQ(j["families"].size(), 2u);
  std::size_t fm = 0;
  for (const auto& f : j["families"]) fm += f["false_miss"].get<std::size_t>();
  EXPECT_EQ(j["total"]["false_miss"].get<std::size_t>(), fm);
  EXPECT_EQ(j["promises"][0]["promise"], "max-ulps 4");
  EXPECT_FALSE(j["promises"][0]["kept"].get<bool>());
  EXPECT_GT(j["promises"][0]["violations"].get<std::size_t>(), 0u);
}

TEST(CheckCli, WritesTheReportWithTheKernelMarked) {
  const auto dir = scratch_dir() / "check_report";
  auto r = run_rayproof("check --method cramer-float --count 20 --families tri_edge,tri_generic --compare float,robust --out " +
                        dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string svg = slurp(dir / "error_vs_time.svg"), md = slurp(dir / "report.md"), csv = slurp(dir / "report.csv");
  EXPECT_NE(svg.find("cramer-float (checked)"), std::string::npos);
  EXPECT_NE(md.find("kernel under test: cramer-float"), std::string::npos);
  for (const char* m : {"cramer-float,tri_edge", "float,tri_edge", "robust,tri_generic"})
    EXPECT_NE(csv.find(m), std::string::npos) << m;
}

TEST(CheckCli, BadOptionsGetClearErrors) {
  struct Bad {
    const char* args;
    const char* message;
  } bad[] = {
      {"check --count 10", "name one kernel"},
      {"check --method float --method2 x", "method2"},
      {"check --method nosuch", "unknown method 'nosuch'"},
      {"check --method float --expect leakproof", "unknown promise 'leakproof'"},
      {"check --method float --families nosuch", "unknown family 'nosuch'"},
      {"check --method float --families tri_generic --expect watertight", "tri_edge and tri_vertex"},
      {"check --method float --mesh generated --max-ulps 3", "apply to the families"},
      {"check --method float --mesh /nonexistent/x.off", "/nonexistent/x.off"},
      {"check --method float --count 1", "--count"},
  };
  for (const auto& b : bad) {
    auto r = run_rayproof(b.args);
    // Our own checks exit with 2; CLI11's parse errors (unknown option, out of range) with its codes.
    EXPECT_NE(r.status, 0) << b.args;
    EXPECT_NE(r.status, 1) << b.args;  // 1 means a broken promise
    const std::string args = b.args;
    if (args.find("--method2") == std::string::npos && args.find("--count 1") == std::string::npos) {
      EXPECT_EQ(r.status, 2) << b.args;
    }
    EXPECT_NE((r.err + r.out).find(b.message), std::string::npos) << b.args << ": " << r.err;
  }
}

TEST(CheckMesh, RobustNeverLeaksAndNaiveFloatDoes) {
  verify::MeshCheckOptions opt;
  opt.finder = scene::find_scene_method("certified", registry::all_methods());
  verify::MeshFuzzOptions g;
  g.seed = 11;
  std::uint64_t robust_leaks = 0, float_leaks = 0, rays = 0, without = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    verify::MeshUnderTest mt;
    std::mt19937_64 rng;
    verify::MeshShape shape;
    mt.mesh = verify::fuzz_mesh(g, i, shape, mt.interior, rng);
    mt.name = "generated";
    ASSERT_FALSE(verify::closed_mesh_problem(mt.mesh).has_value());
    const auto r = verify::check_mesh(method("robust"), mt, opt);
    const auto f = verify::check_mesh(method("float"), mt, opt);
    robust_leaks += r.leaks, float_leaks += f.leaks, rays += r.rays, without += r.rays_without_candidates;
    EXPECT_EQ(r.rays, f.rays);
    for (const auto& leak : f.reproducers) {
      ASSERT_FALSE(leak.candidates.empty());
      for (const auto& c : leak.candidates) {
        EXPECT_NE(c.finder_contact, Contact::miss);
        EXPECT_EQ(method("float").run(c.input).contact, c.answer.contact);  // the reproducer reproduces
        EXPECT_FALSE(verify::touches(c.answer));
      }
    }
  }
  EXPECT_GT(rays, 1000u);
  EXPECT_EQ(without, 0u);
  EXPECT_EQ(robust_leaks, 0u);
  EXPECT_GT(float_leaks, 0u);
}

TEST(CheckMesh, UserMeshFileAndOpenMeshes) {
  // An octahedron written as a file: closed; one interior point found; robust does not leak.
  const auto off = rayproof::testing::write_file(
      "octa.off", "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
                  "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  auto r = run_rayproof("check --method robust --mesh " + off.string() + " --interior 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["meshes"][0]["rays"].get<int>(), 2 * (6 + 12));  // vertices and edges, two directions each
  EXPECT_EQ(j["meshes"][0]["leaks"].get<int>(), 0);
  EXPECT_TRUE(j["watertight"].get<bool>());

  const auto open = rayproof::testing::write_file("open.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  auto o = run_rayproof("check --method robust --mesh " + open.string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("not closed"), std::string::npos) << o.err;

  auto g = run_rayproof("check --method float --mesh generated --meshes 3 --seed 11");
  EXPECT_EQ(g.status, 1) << g.out;
  EXPECT_NE(g.out.find("Promise watertight: BROKEN by "), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("# leak 1 of "), std::string::npos) << g.out;
}

TEST(CheckMesh, CgalSphereRobustZeroFloatLeaks) {
  const std::string sphere = std::string(RAYPROOF_CGAL_MESHES) + "/sphere966.off";
  if (!std::filesystem::exists(sphere)) GTEST_SKIP() << "CGAL's data archive is not installed";
  auto r = run_rayproof("check --method robust --mesh " + sphere + " --interior 1 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["meshes"][0]["leaks"].get<int>(), 0);
  auto f = run_rayproof("check --method float --mesh " + sphere + " --interior 1 --json");
  EXPECT_EQ(f.status, 1) << f.err;
  EXPECT_GT(nlohmann::json::parse(f.out)["meshes"][0]["leaks"].get<int>(), 0);
}

#if defined(RAYPROOF_PLUGIN_DIR) && defined(RAYPROOF_EXAMPLES_DIR)
// Users' kernels through --exec and --plugin: the naive Möller–Trumbore in Python (a child process
// over the line protocol) and in C (a plugin) leak alike on the generated meshes; robust wrapped as a
// plugin does not leak; the Python kernel breaks --expect watertight on the families.
TEST(CheckUserKernels, ExecAndPluginOnMeshesAndFamilies) {
  const std::string py = std::string("'mt-py=python3 ") + RAYPROOF_EXAMPLES_DIR + "/python/moller_trumbore.py'";
  const std::string c = std::string("mt-c=") + RAYPROOF_PLUGIN_DIR + "/moller_trumbore_c.so";
  const std::string robust = std::string("robust-plugin=") + RAYPROOF_PLUGIN_DIR + "/plugin_robust.so";
  const std::string meshes = " --mesh generated --meshes 4 --seed 11 --json";
  auto leaks = [](const std::string& out) {
    int n = 0;
    const auto j = nlohmann::json::parse(out);
    for (const auto& m : j["meshes"]) n += m["leaks"].get<int>();
    return n;
  };
  auto p = run_rayproof("check --exec " + py + meshes);
  ASSERT_EQ(p.status, 1) << p.err;
  auto cp = run_rayproof("check --plugin-in-process --plugin " + c + meshes);
  ASSERT_EQ(cp.status, 1) << cp.err;
  EXPECT_GT(leaks(p.out), 0);
  EXPECT_EQ(leaks(p.out), leaks(cp.out));  // the same algorithm in the same arithmetic
  auto r = run_rayproof("check --plugin-in-process --plugin " + robust + meshes);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(leaks(r.out), 0);

  auto f = run_rayproof("check --exec " + py + " --families tri_edge,tri_vertex --count 60 --expect watertight --reproducers 0");
  EXPECT_EQ(f.status, 1) << f.err;
  EXPECT_NE(f.out.find("Promise watertight: BROKEN by "), std::string::npos) << f.out;

  auto z = run_rayproof("fuzz --mesh --cases 2 --seed 11 --methods robust --exec " + py);
  EXPECT_EQ(z.status, 0) << z.err;  // a user kernel's leaks are findings
  EXPECT_NE(z.out.find("mt-py"), std::string::npos) << z.out;
}
#endif
