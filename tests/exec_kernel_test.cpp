// User kernels over the line protocol (--exec, docs/kernel_protocol.md): the built-in float method
// through `rayproof serve` gives the in-process tallies; kernels that crash, hang, exit early, print
// garbage or buffer until end of input are each handled, the culprit case identified, the other
// cases still answered; coarse answers are judged by hit/miss, t and barycentrics.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "registry/registry.h"
#include "cli_support.h"
#include "stats_support.h"
#include "gen/families.h"
#include "io/case_file.h"
#include "methods/exec_kernel.h"
#include "verify/differential.h"
#include "verify/exact_method.h"

using namespace rayproof;
using rayproof::testing::expect_same_tallies;

namespace {

const std::string kKernel = EXEC_TEST_KERNEL;

Method make(const std::string& spec, double timeout = 5) {
  ExecOptions o;
  o.timeout_seconds = timeout;
  auto m = make_exec_method(spec, o);
  if (auto* e = std::get_if<std::string>(&m)) {
    ADD_FAILURE() << *e;
    return Method{};
  }
  return std::get<Method>(std::move(m));
}

std::vector<io::Case> triangles(std::size_t n) {
  return gen::generate(*gen::find_family("tri_generic"), n, 11, gen::Precision::float64);
}

std::vector<io::CaseResult> answers(const Method& m, const std::vector<io::Case>& cases) {
  std::vector<io::CaseResult> out(cases.size());
  m.classify_many(cases, out);
  return out;
}

/// No child of this process is left unreaped.
void expect_no_children() { EXPECT_EQ(::waitpid(-1, nullptr, WNOHANG), -1); }

/// The same tallies, and the external kernel (b) answered every case in full.
void expect_same_stats(const verify::Stats& a, const verify::Stats& b, const std::string& where) {
  expect_same_tallies(a, b, where);
  EXPECT_EQ(b.kernel_failures, 0u) << where;
  EXPECT_EQ(b.coarse, 0u) << where;
}

}  // namespace

TEST(ExecKernel, BuiltInFloatThroughServeGivesTheInProcessTallies) {
  std::vector<io::Case> cases;
  std::size_t ray_families = 0;
  for (const auto& f : gen::families()) {
    if (f.kind == io::Kind::tritri) continue;  // float answers rays only
    ++ray_families;
    auto c = gen::generate(f, 24, 5, gen::Precision::float64);
    cases.insert(cases.end(), c.begin(), c.end());
  }
  const Method* inproc = registry::all_methods().find("float");
  ASSERT_NE(inproc, nullptr);
  const Method ext = make(std::string("f=") + RAYPROOF_BIN + " serve --method float");
  ASSERT_TRUE(ext.classify_batch);
  EXPECT_EQ(ext.precision, Precision::float32);
  EXPECT_EQ(ext.kinds, inproc->kinds);
  const auto exact = verify::exact_answers(cases);
  const auto cmp = verify::compare(cases, exact, {inproc, &ext}, 0);
  ASSERT_EQ(cmp.groups.size(), ray_families);
  std::size_t total = 0;
  for (const auto& g : cmp.groups) {
    const auto a = cmp.stats.find({"float", g}), b = cmp.stats.find({"f", g});
    ASSERT_TRUE(a != cmp.stats.end() && b != cmp.stats.end()) << g;
    expect_same_stats(a->second, b->second, g);
    total += b->second.cases;
  }
  EXPECT_EQ(total, cases.size());
  EXPECT_TRUE(ext.take_failures().empty());
  // Fresh kernels per batch: the same answers again, and one case alone.
  EXPECT_EQ(ext.run(cases[3]), inproc->run(cases[3]));
  expect_no_children();
}

TEST(ExecKernel, DeclarationFromTheKernelOrTheSpec) {
  const Method m = make("mt=" + kKernel + " mt header");
  EXPECT_EQ(m.name, "mt");
  EXPECT_EQ(m.precision, Precision::float64);
  EXPECT_EQ(m.kinds, std::vector<io::Kind>{io::Kind::triangle});
  const Method s = make("s:float:sphere,box=" + kKernel);
  EXPECT_EQ(s.precision, Precision::float32);
  EXPECT_EQ(s.kinds, (std::vector<io::Kind>{io::Kind::sphere, io::Kind::box}));
  for (const char* bad : {"noequals", "=cmd", "x=", "bad name=cmd", "x:quad:triangle=cmd", "x:float:cone=cmd",
                          "x:float=cmd", "x=true", "x=echo hello", "x=echo rayproof-kernel 2 double triangle",
                          "x=echo rayproof-kernel 1 double triangle,cone"}) {
    const auto r = make_exec_method(bad, ExecOptions{1, 20});
    ASSERT_TRUE(std::holds_alternative<std::string>(r)) << bad;
    EXPECT_FALSE(std::get<std::string>(r).empty()) << bad;
  }
  expect_no_children();
}

TEST(ExecKernel, FloatKernelsReadFloatRoundedInputsAndOtherKindsAreNotSent) {
  // The kernel answers `hit X` with X the first number it read, as written.
  const Method m = make("echo:float:triangle=awk '{print \"hit \" $2}'");
  auto cases = triangles(20);
  cases[4].v[0] = 0.1;
  cases.push_back(gen::generate(*gen::find_family("sph_generic"), 1, 3, gen::Precision::float64)[0]);
  const auto out = answers(m, cases);
  for (std::size_t i = 0; i + 1 < cases.size(); ++i) {
    ASSERT_TRUE(out[i].t) << i;
    EXPECT_EQ(*out[i].t, double(float(cases[i].v[0]))) << i;
    EXPECT_EQ(out[i].form, io::AnswerForm::coarse);
  }
  EXPECT_EQ(out.back().contact, Contact::error);  // a sphere: not declared, not sent
  EXPECT_TRUE(m.take_failures().empty());
}

namespace {
/// Runs `mode` on 150 triangles with case 97 poisoned; checks the failure is pinned on it and every
/// other case has the well-behaved kernel's answer.
void check_failure_pinned(const std::string& mode, const std::string& what, double timeout = 5) {
  auto cases = triangles(150);
  cases[97].v[0] = 777;
  const Method good = make("good:double:triangle=" + kKernel + " mt");
  const Method bad = make("bad:double:triangle=" + kKernel + " " + mode, timeout);
  const auto want = answers(good, cases);
  const auto got = answers(bad, cases);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    if (i == 97) EXPECT_EQ(got[i].contact, Contact::error) << mode;
    else EXPECT_EQ(got[i], want[i]) << mode << " case " << i;
  }
  const auto failures = bad.take_failures();
  ASSERT_EQ(failures.size(), 1u) << mode;
  EXPECT_NE(failures[0].what.find(what), std::string::npos) << failures[0].what;
  EXPECT_EQ(io::format_case(failures[0].input), io::format_case(cases[97]));
  EXPECT_TRUE(bad.take_failures().empty());  // drained
  EXPECT_TRUE(good.take_failures().empty());
  expect_no_children();
}
}  // namespace

TEST(ExecKernel, CrashIsPinnedOnItsCase) { check_failure_pinned("crash", "crashed (signal 11"); }
TEST(ExecKernel, HangIsPinnedOnItsCase) { check_failure_pinned("hang", "timed out", 0.3); }
TEST(ExecKernel, EarlyExitIsPinnedOnItsCase) { check_failure_pinned("exit", "exited early (status 3)"); }
TEST(ExecKernel, GarbageIsPinnedOnItsCase) { check_failure_pinned("garbage", "unreadable answer 'banana'"); }

TEST(ExecKernel, KernelThatBuffersUntilEndOfInputIsAnswered) {
  const auto cases = triangles(3000);  // far more than a pipe holds
  const Method good = make("good:double:triangle=" + kKernel + " mt");
  const Method eof = make("eof:double:triangle=" + kKernel + " eof");
  EXPECT_EQ(answers(eof, cases), answers(good, cases));
  EXPECT_TRUE(eof.take_failures().empty());
  expect_no_children();
}

TEST(ExecKernel, DroppedAfterTwentyFailures) {
  auto cases = triangles(60);
  for (std::size_t i = 10; i < 35; ++i) cases[i].v[0] = 777;
  const Method bad = make("bad:double:triangle=" + kKernel + " exit");
  const auto got = answers(bad, cases);
  EXPECT_EQ(bad.take_failures().size(), 20u);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_NE(got[i].contact, Contact::error) << i;
  for (std::size_t i = 10; i < cases.size(); ++i) EXPECT_EQ(got[i].contact, Contact::error) << i;
  // Dropped for the rest of the run: no process is started any more.
  EXPECT_EQ(bad.run(triangles(1)[0]).contact, Contact::error);
  EXPECT_TRUE(bad.take_failures().empty());
  expect_no_children();
}

TEST(ExecKernel, CoarseAnswersAreJudgedByHitMissTAndBarycentrics) {
  // p0 p1 p2 = (0,0,0) (1,0,0) (0,1,0); the ray through (0.25, 0.5) hits at t = 1 with b1 = 0.25, b2 = 0.5.
  auto tri = [](double x, double y) {
    io::Case c;
    c.kind = io::Kind::triangle;
    c.v = {x, y, -1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    c.family = "tri";
    return c;
  };
  io::Case inside;  // origin inside a sphere of radius 2: `inside -2 2`, first contact t = 2
  inside.kind = io::Kind::sphere;
  inside.v = {0, 0, 0, 1, 0, 0, 0, 0, 0, 2};
  inside.family = "sph";
  const std::vector<io::Case> cases = {tri(0.25, 0.5), tri(0.25, 0.5), tri(2, 2), tri(2, 2), tri(0.25, 0.5), inside, inside};
  // The kernel prints fixed answers, one per case, whatever it reads.
  const Method m = make(
      "k:double:triangle,sphere=printf 'hit 1 0.25 0.625\\nmiss\\nhit\\nmiss\\nhit 1\\nhit 2\\nhit 0x1.0000000000001p+1\\n'");
  const auto exact = verify::exact_answers(cases);
  const auto cmp = verify::compare(cases, exact, {&m}, 100, 0);
  const auto& t = cmp.stats.at({"k", "tri"});
  EXPECT_EQ(t.cases, 5u);
  EXPECT_EQ(t.coarse, 5u);
  EXPECT_EQ(t.false_miss, 1u);  // case 1
  EXPECT_EQ(t.false_hit, 1u);   // case 2
  EXPECT_EQ(t.wrong_hit_class + t.wrong_class + t.kernel_failures, 0u);
  EXPECT_EQ(t.ulps, (std::vector<std::uint64_t>{0, 0}));     // cases 0 and 4
  EXPECT_EQ(t.bary_errors, std::vector<double>{0.125});      // case 0: b2 off by 1/8
  const auto& s = cmp.stats.at({"k", "sph"});
  EXPECT_EQ(s.cases, 2u);
  EXPECT_EQ(s.class_errors(), 0u);
  EXPECT_EQ(s.ulps, (std::vector<std::uint64_t>{0, 1}));     // against T2 = 2
  ASSERT_EQ(cmp.mismatches.size(), 3u);  // false miss, false hit, 1 ulp (tolerance 0)
  EXPECT_EQ(cmp.mismatches[0].verdict, verify::Verdict::false_miss);
  EXPECT_EQ(io::format_answer(cmp.mismatches[0].got), "miss");
  EXPECT_EQ(cmp.mismatches[1].verdict, verify::Verdict::false_hit);
  EXPECT_EQ(io::format_answer(cmp.mismatches[1].got), "hit");
  const auto b = verify::exact_barycentrics(cases[0]);
  ASSERT_TRUE(b);
  EXPECT_EQ((*b)[0], 0.25);
  EXPECT_EQ((*b)[1], 0.5);
  expect_no_children();
}

TEST(ExecKernel, VerifyListsKernelFailuresWithTheirReproducer) {
  auto cases = triangles(40);
  cases[7].v[0] = 777;
  std::string text;
  for (const auto& c : cases) io::append_case_line(text, c);
  const auto file = rayproof::testing::write_file("exec_verify.txt", text);
  const auto r = rayproof::testing::run_rayproof("verify --methods float --exec 'c:double:triangle=" + kKernel +
                                                 " crash' " + file.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("kfail"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("# kernel failures"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(io::format_case(cases[7]) + "  # c: crashed (signal 11"), std::string::npos) << r.out;
  const auto j = rayproof::testing::run_rayproof("verify --json --methods float --exec 'c:double:triangle=" + kKernel +
                                                 " crash' " + file.string());
  EXPECT_NE(j.out.find("\"kernel_failures\": 1"), std::string::npos) << j.out;
  const auto bad = rayproof::testing::run_rayproof("verify --exec 'nocommand=' " + file.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("no command"), std::string::npos) << bad.err;
  const auto taken = rayproof::testing::run_rayproof("verify --exec 'float=" + kKernel + " mt header' " + file.string());
  EXPECT_EQ(taken.status, 2);
  EXPECT_NE(taken.err.find("taken"), std::string::npos) << taken.err;
  EXPECT_EQ(rayproof::testing::run_rayproof("serve --method nosuch").status, 2);
  const auto served = rayproof::testing::run_rayproof("serve --method double", io::format_case(cases[0]) + "\nbogus\n");
  EXPECT_EQ(served.status, 0);
  EXPECT_EQ(served.out, "rayproof-kernel 1 double plane,sphere,ellipsoid,triangle,box,disk\n" +
                            io::format_result(registry::all_methods().find("double")->run(cases[0])) + "\nerror - -\n");
}

TEST(ExecKernel, KernelThatReadsNothingDoesNotKillRayproofWithSigpipe) {
  // Megabytes of input to a kernel that exits at once: writes fail with EPIPE, never SIGPIPE.
  const auto cases = triangles(20000);
  const Method quit = make("quit:double:triangle=exit 0");
  const auto got = answers(quit, cases);
  EXPECT_EQ(std::count_if(got.begin(), got.end(), [](const io::CaseResult& r) { return r.contact == Contact::error; }),
            std::ptrdiff_t(cases.size()));
  const auto failures = quit.take_failures();
  ASSERT_EQ(failures.size(), 20u);  // then dropped
  EXPECT_NE(failures[0].what.find("exited early (status 0)"), std::string::npos) << failures[0].what;
  expect_no_children();
}

// A user's kernel is a method like the others for --methods, in verify, report and
// fuzz (cases and --mesh): named alone it runs alone, named in a list it takes its place in the order.
TEST(ExecKernel, MethodsNamesYourKernelInVerifyReportAndFuzz) {
  using rayproof::testing::run_rayproof;
  std::string text;
  for (const auto& c : triangles(30)) io::append_case_line(text, c);
  const auto file = rayproof::testing::write_file("exec_methods.txt", text).string();
  const std::string mine = " --exec 'mine:double:triangle=" + kKernel + " mt' ";
  auto rows_of = [](const std::string& out) {  // the method column of a verify table, in order
    std::vector<std::string> names;
    std::size_t at = 0;
    while (at < out.size()) {
      const auto end = out.find('\n', at);
      const std::string line = out.substr(at, end == std::string::npos ? std::string::npos : end - at);
      at = end == std::string::npos ? out.size() : end + 1;
      if (line.empty() && !names.empty()) break;  // the table ends at its first blank line
      const std::string first = line.substr(0, line.find(' '));
      if (!first.empty() && first != "method" && first[0] != '#' && (names.empty() || names.back() != first))
        names.push_back(first);
    }
    return names;
  };

  auto v = run_rayproof("verify --methods mine" + mine + file);
  ASSERT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(rows_of(v.out), (std::vector<std::string>{"mine"})) << v.out;
  v = run_rayproof("verify --methods mine,double" + mine + file);  // the order of the list
  ASSERT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(rows_of(v.out), (std::vector<std::string>{"mine", "double"})) << v.out;
  v = run_rayproof("verify --methods double" + mine + file);  // given but not named: still run, after
  ASSERT_EQ(v.status, 0) << v.err;
  EXPECT_EQ(rows_of(v.out), (std::vector<std::string>{"double", "mine"})) << v.out;
  v = run_rayproof("verify --methods yours" + mine + file);
  EXPECT_EQ(v.status, 2);
  EXPECT_NE(v.err.find("unknown method 'yours'"), std::string::npos) << v.err;
  EXPECT_NE(v.err.find("your kernels: mine"), std::string::npos) << v.err;

  const auto dir = rayproof::testing::scratch_dir() / "exec_methods_report";
  std::filesystem::remove_all(dir);
  const auto r = run_rayproof("report --count 4 --families tri_edge --irradiance-samples 0 --methods mine" + mine +
                              "--out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string md = rayproof::testing::slurp(dir / "report.md");
  EXPECT_NE(md.find("methods: mine\n"), std::string::npos) << md.substr(0, 2000);

  const auto fdir = rayproof::testing::scratch_dir() / "exec_methods_fuzz";
  const auto f = run_rayproof("fuzz --cases 20 --families tri_edge --methods mine" + mine + "--out " + fdir.string());
  EXPECT_NE(f.status, 2) << f.err;
  EXPECT_NE(f.out.find("mine"), std::string::npos) << f.out;
  EXPECT_EQ(f.out.find("\nfloat "), std::string::npos) << f.out;  // no registered method's row: none ran
  EXPECT_EQ(f.out.find("\nrobust "), std::string::npos) << f.out;

  const auto m = run_rayproof("fuzz --mesh --cases 1 --seed 3 --methods mine" + mine);
  EXPECT_NE(m.status, 2) << m.err;
  EXPECT_NE(m.out.find("mine "), std::string::npos) << m.out;
  EXPECT_EQ(m.out.find("robust"), std::string::npos) << m.out;  // no built-in mesh method ran
  expect_no_children();
}
