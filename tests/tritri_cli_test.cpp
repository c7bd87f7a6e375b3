// Triangle pairs end to end through the tool: classify, verify, fuzz and report on `tritri` case
// files and families, `check` on a pair kernel over the line protocol (rayproof serve), as a C plugin
// (examples/c_plugin/tritri_moller.c) and in Python (examples/python/tritri_guigue_devillers.py),
// with the tallies counted again here from the kernels and exact arithmetic on the same pairs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "gen/families.h"
#include "io/case_file.h"
#include "methods/plugin_kernel.h"
#include "rayproof/tritri.h"
#include "rayproof/verify/exact.h"
#include "verify/check.h"
#include "verify/check_text.h"

namespace rayproof {
namespace {

using testing::run_rayproof;
using testing::scratch_dir;
using testing::slurp;
using testing::write_file;

template <class T>
Triangle<T> tri(const io::Case& c, std::size_t at) {
  auto p = [&](std::size_t i) {
    return Vec3<T>{static_cast<T>(c.v[at + 3 * i]), static_cast<T>(c.v[at + 3 * i + 1]), static_cast<T>(c.v[at + 3 * i + 2])};
  };
  return {p(0), p(1), p(2)};
}

/// False meets and false disjoints of a classic kernel on `cases` (as the method sees them: rounded
/// to float for a float kernel), against exact::tritri; degenerate and invalid pairs not judged.
struct Tally {
  std::size_t judged = 0, false_meets = 0, false_disjoint = 0;
};
template <class T>
Tally count_directly(const std::vector<io::Case>& cases, TriTriMethod m) {
  Tally t;
  for (const auto& given : cases) {
    const io::Case c = std::is_same_v<T, float> ? io::round_to_float(given) : given;
    const TriTri want = exact::tritri(tri<double>(c, 0), tri<double>(c, 9));
    if (want == TriTri::degenerate || want == TriTri::invalid) continue;
    ++t.judged;
    const bool got = tritri_intersect(tri<T>(c, 0), tri<T>(c, 9), m);
    if (got && !meets(want)) ++t.false_meets;
    if (!got && meets(want)) ++t.false_disjoint;
  }
  return t;
}

/// The pairs `check` and `report` build for a family: count/2 in float precision, the rest in double.
std::vector<io::Case> halves(const std::string& family, std::size_t count, std::uint64_t seed) {
  std::vector<io::Case> out;
  for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
    const std::size_t n = p == gen::Precision::float32 ? count / 2 : count - count / 2;
    for (auto& c : gen::generate(*gen::find_family(family), n, seed, p)) out.push_back(std::move(c));
  }
  return out;
}

/// The cases as a case file, with a `# family NAME` line where the family changes.
std::string case_file(const std::vector<io::Case>& cases) {
  std::string s, family;
  for (const auto& c : cases) {
    if (c.family != family) s += "# family " + c.family + "\n", family = c.family;
    io::append_case_line(s, c);
  }
  return s;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) v.push_back(l);
  return v;
}

// --- classify ----------------------------------------------------------------------------------------

TEST(TriTriCli, ClassifyAnswersEachPairWithItsClassAndBadLinesWithErrors) {
  // By construction: b's vertex (1, 1, 0) inside a (touching); b far above a (disjoint); b's edge
  // through a's interior (crossing). The fourth line has 17 numbers.
  const std::string in =
      "tritri 0 0 0 4 0 0 0 4 0 1 1 0 1 1 1 2 1 1\n"
      "tritri 0 0 0 4 0 0 0 4 0 0 0 5 1 0 5 0 1 5\n"
      "tritri 0 0 0 4 0 0 0 4 0 1 1 -1 1 1 1 2 1 1\n"
      "tritri 0 0 0 4 0 0 0 4 0 1 1 0 1 1 1 2 1\n";
  for (const char* m : {"exact", "certified"}) {
    const auto r = run_rayproof(std::string("classify --method ") + m + " -", in);
    EXPECT_EQ(r.status, 1) << m << r.err;
    const auto l = lines_of(r.out);
    ASSERT_EQ(l.size(), 4u) << m << r.out;
    EXPECT_EQ(l[0], "touching") << m;
    EXPECT_EQ(l[1], "disjoint") << m;
    EXPECT_EQ(l[2], "crossing") << m;
    EXPECT_EQ(l[3].rfind("error", 0), 0u) << m << l[3];
    EXPECT_NE(r.err.find("-:4: tritri needs 18 numbers, got 17"), std::string::npos) << r.err;
  }
}

// --- verify: tallies equal the kernels counted here ------------------------------------------------

TEST(TriTriCli, VerifyTalliesEqualTheKernelsCountedDirectly) {
  const std::vector<std::string> fams = {"tritri_shared_vertex", "tritri_coplanar_touching", "tritri_near_coplanar"};
  std::vector<io::Case> all;
  for (const auto& f : fams)
    for (auto& c : gen::generate(*gen::find_family(f), 120, 5, gen::Precision::float64)) all.push_back(std::move(c));
  const auto file = write_file("pairs.txt", case_file(all));
  const auto r = run_rayproof("verify --json --methods moller-float,gd-double,certified " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;  // verify reports; its exit status is not the kernels' errors
  const auto j = nlohmann::json::parse(r.out);
  std::size_t rows = 0, classic_errors = 0;
  for (const auto& row : j.at("rows")) {
    const std::string m = row.at("method"), fam = row.at("family");
    std::vector<io::Case> cases;
    for (const auto& c : all)
      if (c.family == fam) cases.push_back(c);
    ASSERT_FALSE(cases.empty()) << fam;
    ++rows;
    if (m == "certified") {
      EXPECT_EQ(row.at("class_errors").get<std::size_t>(), 0u) << fam;
      EXPECT_EQ(row.at("cases").get<std::size_t>(), cases.size()) << fam;
      continue;
    }
    const Tally t = m == "moller-float" ? count_directly<float>(cases, TriTriMethod::moller)
                                        : count_directly<double>(cases, TriTriMethod::guigue_devillers);
    EXPECT_EQ(row.at("cases").get<std::size_t>(), t.judged) << m << " " << fam;
    EXPECT_EQ(row.at("false_hit").get<std::size_t>(), t.false_meets) << m << " " << fam;
    EXPECT_EQ(row.at("false_miss").get<std::size_t>(), t.false_disjoint) << m << " " << fam;
    classic_errors += t.false_meets + t.false_disjoint;
  }
  EXPECT_EQ(rows, 3 * fams.size());
  EXPECT_GT(classic_errors, 0u);  // the comparison above compares something
}

// --- fuzz: certified makes no class error on any pair family ----------------------------------------

TEST(TriTriCli, FuzzCertifiedHasNoClassErrorOnEveryPairFamily) {
  std::string fams;
  std::size_t n = 0;
  for (const auto& f : gen::families())
    if (f.kind == io::Kind::tritri) fams += (fams.empty() ? "" : ",") + f.name, ++n;
  ASSERT_EQ(n, 16u);
  const auto dir = scratch_dir() / "fuzz";
  const auto summary = scratch_dir() / "fuzz.json";
  const auto r = run_rayproof("fuzz --methods certified,gd-float --families " + fams + " --cases 3200 --seed 4 --jobs 1 --out " +
                              dir.string() + " --summary " + summary.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(summary));
  std::size_t certified_rows = 0, certified_cases = 0, gd_errors = 0;
  for (const auto& row : j.at("stats")) {
    const std::size_t errors = row.at("false_hit").get<std::size_t>() + row.at("false_miss").get<std::size_t>() +
                               row.at("wrong_hit_class").get<std::size_t>() + row.at("wrong_class").get<std::size_t>();
    if (row.at("method") == "certified") {
      ++certified_rows;
      certified_cases += row.at("cases").get<std::size_t>();
      EXPECT_EQ(errors, 0u) << row.at("family");
    } else {
      gd_errors += errors;
    }
  }
  EXPECT_EQ(certified_rows, 16u);
  EXPECT_GE(certified_cases, 3000u);
  EXPECT_GT(gd_errors, 0u);  // the same judgement finds the float kernel's errors
}

// --- report: the pair section, with verify's tallies ------------------------------------------------

TEST(TriTriCli, ReportHasAPairSectionWhoseTalliesAreTheKernels) {
  const auto dir = scratch_dir() / "report";
  const auto r = run_rayproof("report --families tritri_shared_edge,tritri_coplanar --methods certified,moller-float "
                              "--pair-count 80 --seed 2 --stability-count 0 --irradiance-samples 0 --out " + dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string md = slurp(dir / "report.md");
  EXPECT_NE(md.find("| false meets | false disjoint |"), std::string::npos) << md;
  EXPECT_NE(md.find("triangle pairs: 2 families x 80"), std::string::npos) << md;
  const std::string csv = slurp(dir / "report.csv");
  std::size_t checked = 0;
  for (const auto& line : lines_of(csv)) {
    if (line.rfind("moller-float,", 0) != 0) continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_GE(f.size(), 8u) << line;
    const Tally t = count_directly<float>(halves(f[1], 80, 2), TriTriMethod::moller);
    EXPECT_EQ(std::stoul(f[4]), t.judged) << line;
    EXPECT_EQ(std::stoul(f[6]), t.false_meets) << line;
    EXPECT_EQ(std::stoul(f[7]), t.false_disjoint) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 2u) << csv;
}

// --- check: a pair kernel of yours ---------------------------------------------------------------------

/// Runs `check` on `kernel_option` (an --exec or --plugin option) over the families, as JSON.
nlohmann::json check_json(const std::string& kernel_option, const std::string& families, std::size_t count, int& status) {
  const auto r = run_rayproof("check " + kernel_option + " --families " + families + " --count " +
                              std::to_string(count) + " --seed 1 --json --expect no-false-negative");
  status = r.status;
  EXPECT_TRUE(r.status == 0 || r.status == 1) << r.err;
  return nlohmann::json::parse(r.out.empty() ? "{}" : r.out);
}

/// The first false-disjoint reproducer's case line reproduces: `verify` with the same kernel option
/// finds the kernel's one false miss on it, and exact classifies it as a meeting class.
void expect_reproducer_reproduces(const nlohmann::json& j, const std::string& kernel_option, const std::string& name) {
  for (const auto& fam : j.at("families"))
    for (const auto& rep : fam.at("reproducers")) {
      if (rep.at("verdict") != "false-miss") continue;
      const std::string line = rep.at("case").get<std::string>() + "\n";
      EXPECT_EQ(rep.at("got"), "miss") << line;
      const auto mine = run_rayproof("verify --json " + kernel_option + " --methods " + name + " -", line);
      ASSERT_EQ(mine.status, 0) << mine.err;
      const auto rows = nlohmann::json::parse(mine.out).at("rows");
      ASSERT_EQ(rows.size(), 1u) << mine.out;
      EXPECT_EQ(rows[0].at("false_miss").get<std::size_t>(), 1u) << line << mine.out;
      const auto exact = run_rayproof("classify --method exact -", line);
      const std::string want = exact.out.substr(0, exact.out.find('\n'));
      EXPECT_TRUE(want == "crossing" || want == "touching" || want == "coplanar_overlap" || want == "coplanar_touching")
          << line << want;
      return;
    }
  ADD_FAILURE() << "no false-miss reproducer";
}

TEST(TriTriCheck, ExecPairKernelTalliesAreTheKernelsAndThePromiseFollowsThem) {
  const std::string fams = "tritri_shared_edge,tritri_vertex_on_face";
  const std::string exec = std::string("--exec 'gd=") + RAYPROOF_BIN + " serve --method gd-float'";
  int status = -1;
  const auto j = check_json(exec, fams, 200, status);
  Tally want;
  for (const char* f : {"tritri_shared_edge", "tritri_vertex_on_face"}) {
    const Tally t = count_directly<float>(halves(f, 200, 1), TriTriMethod::guigue_devillers);
    want.judged += t.judged, want.false_meets += t.false_meets, want.false_disjoint += t.false_disjoint;
  }
  const auto& total = j.at("total");
  EXPECT_EQ(total.at("cases").get<std::size_t>(), want.judged);
  EXPECT_EQ(total.at("false_hit").get<std::size_t>(), want.false_meets);
  EXPECT_EQ(total.at("false_miss").get<std::size_t>(), want.false_disjoint);
  EXPECT_EQ(total.at("failures").get<std::size_t>(), 0u);
  EXPECT_EQ(status, want.false_disjoint > 0 ? 1 : 0);
  if (want.false_disjoint > 0) expect_reproducer_reproduces(j, exec, "gd");
}

TEST(TriTriCheck, KernelsThatGiveClassesAreHeldToExactClass) {
  // Every pair of tritri_shared_edge is touching by construction: a kernel that always says
  // `crossing` has the meets-or-not answer right and the class wrong on each one.
  int status = -1;
  const auto j = check_json("--exec 'x:double:tritri=while read l; do echo crossing; done' --expect exact-class",
                            "tritri_shared_edge", 40, status);
  const auto& t = j.at("total");
  EXPECT_EQ(t.at("cases").get<std::size_t>(), 40u);
  EXPECT_EQ(t.at("wrong_hit_class").get<std::size_t>() + t.at("wrong_class").get<std::size_t>(), 40u);
  EXPECT_EQ(t.at("false_hit").get<std::size_t>() + t.at("false_miss").get<std::size_t>(), 0u);
  EXPECT_EQ(status, 1);
  // The certified classifier served over the line protocol keeps the promise.
  const auto c = check_json(std::string("--exec 'c=") + RAYPROOF_BIN + " serve --method certified' --expect exact-class",
                            "tritri_shared_edge,tritri_coplanar", 40, status);
  EXPECT_EQ(c.at("total").at("cases").get<std::size_t>(), 80u);
  EXPECT_EQ(status, 0) << c.dump();
}

TEST(TriTriCheck, GarbageAndCrashesOfAPairKernelAreFailuresWithTheirPair) {
  struct Bad {
    const char* kernel;
    const char* what;
  };
  for (const Bad& b : {Bad{"while read l; do echo hit 1.0; done", "is not an answer to a tritri case"},
                       Bad{"while read l; do echo edge 1.0 -; done", "is not an answer to a tritri case"},
                       Bad{"read l; kill -SEGV $$", "crashed (signal 11"}}) {
    int status = -1;
    const auto j = check_json(std::string("--exec 'bad:double:tritri=") + b.kernel + "'", "tritri_crossing", 4, status);
    EXPECT_EQ(status, 1) << b.kernel;  // no-false-negative counts failures
    EXPECT_EQ(j.at("total").at("failures").get<std::size_t>(), 4u) << b.kernel;
    EXPECT_EQ(j.at("total").at("false_miss").get<std::size_t>() + j.at("total").at("false_hit").get<std::size_t>(), 0u);
    const auto& rep = j.at("families").at(0).at("reproducers").at(0);
    EXPECT_EQ(rep.at("verdict"), "kernel-failure");
    EXPECT_NE(rep.at("what").get<std::string>().find(b.what), std::string::npos) << rep.dump();
    EXPECT_EQ(rep.at("case").get<std::string>().rfind("tritri ", 0), 0u);
  }
}

TEST(TriTriCheck, TheCPluginExampleMissesWhatMollerInFloatMisses) {
  const std::string plugin = std::string(RAYPROOF_PLUGIN_DIR) + "/tritri_moller_c.so";
  const std::string fams = "tritri_shared_vertex,tritri_coplanar_touching";
  int status = -1;
  const auto j = check_json("--plugin mine=" + plugin, fams, 200, status);
  Tally want;
  for (const char* f : {"tritri_shared_vertex", "tritri_coplanar_touching"}) {
    const Tally t = count_directly<float>(halves(f, 200, 1), TriTriMethod::moller);
    want.judged += t.judged, want.false_meets += t.false_meets, want.false_disjoint += t.false_disjoint;
  }
  const auto& total = j.at("total");
  EXPECT_EQ(total.at("cases").get<std::size_t>(), want.judged);
  EXPECT_EQ(total.at("false_hit").get<std::size_t>(), want.false_meets);
  EXPECT_EQ(total.at("false_miss").get<std::size_t>(), want.false_disjoint);
  EXPECT_GT(want.false_disjoint, 0u);  // the example is the textbook test, caught
  EXPECT_EQ(status, 1);
  expect_reproducer_reproduces(j, "--plugin mine=" + plugin, "mine");
}

TEST(TriTriCheck, ThePythonExampleIsJudgedAndItsReproducersReproduce) {
  const std::string exec = std::string("--exec 'gd-python=/usr/bin/python3 ") + RAYPROOF_EXAMPLES_DIR +
                           "/python/tritri_guigue_devillers.py'";
  int status = -1;
  const auto j = check_json(exec, "tritri_shared_vertex,tritri_vertex_on_face,tritri_crossing", 100, status);
  const auto& total = j.at("total");
  EXPECT_GT(total.at("cases").get<std::size_t>(), 0u);
  EXPECT_EQ(total.at("failures").get<std::size_t>(), 0u);
  const std::size_t fd = total.at("false_miss").get<std::size_t>();
  EXPECT_EQ(status, fd > 0 ? 1 : 0);
  for (const auto& fam : j.at("families")) {
    if (fam.at("family") == "tritri_crossing") {
      EXPECT_EQ(fam.at("false_miss").get<std::size_t>(), 0u);  // clear crossings: G-D is right
    }
  }
  if (fd > 0) expect_reproducer_reproduces(j, exec, "gd-python");
}

// --- the plugin's answers to pairs, and check's words for pairs ------------------------------------------

TEST(TriTriPlugin, PairAnswersAndAnswersThatDoNotFitTheKind) {
  auto ok = [](io::Kind k, rayproof_answer a) {
    auto r = plugin_answer_to_result(k, a);
    EXPECT_TRUE(std::holds_alternative<io::CaseResult>(r)) << a.cls;
    return std::holds_alternative<io::CaseResult>(r) ? io::format_answer(std::get<io::CaseResult>(r)) : "";
  };
  EXPECT_EQ(ok(io::Kind::tritri, {RAYPROOF_COARSE_HIT, 0, 0, 0, 0, 0}), "hit");
  EXPECT_EQ(ok(io::Kind::tritri, {RAYPROOF_COARSE_MISS, 0, 0, 0, 0, 0}), "miss");
  EXPECT_EQ(ok(io::Kind::tritri, {RAYPROOF_TOUCHING, 0, 0, 0, 0, 0}), "touching");
  EXPECT_EQ(ok(io::Kind::tritri, {RAYPROOF_DEGENERATE, 0, 0, 0, 0, 0}), "degenerate");
  EXPECT_EQ(ok(io::Kind::tritri, {RAYPROOF_COPLANAR_TOUCHING, 0, 0, 0, 0, 0}), "coplanar_touching");
  const std::vector<std::pair<io::Kind, rayproof_answer>> bad = {
      {io::Kind::tritri, {RAYPROOF_EDGE, RAYPROOF_HAS_T, 1, 0, 0, 0}},      // a ray class for a pair
      {io::Kind::tritri, {RAYPROOF_HIT, 0, 0, 0, 0, 0}},                    // a ray class for a pair
      {io::Kind::tritri, {RAYPROOF_COARSE_HIT, RAYPROOF_HAS_T, 1, 0, 0, 0}},  // a t on a pair
      {io::Kind::tritri, {RAYPROOF_CROSSING, RAYPROOF_HAS_T, 1, 0, 0, 0}},    // a t on a pair's class
      {io::Kind::tritri, {RAYPROOF_NO_ANSWER, 0, 0, 0, 0, 0}},
      {io::Kind::triangle, {RAYPROOF_TOUCHING, 0, 0, 0, 0, 0}},  // a pair's class for a ray
      {io::Kind::tritri, {14, 0, 0, 0, 0, 0}},                   // `error` is no class
  };
  for (const auto& [k, a] : bad)
    EXPECT_TRUE(std::holds_alternative<std::string>(plugin_answer_to_result(k, a))) << a.cls << " " << a.has;
}

TEST(TriTriCheckText, PairResultsAreWordedAsMeetsAndDisjoint) {
  verify::CheckResult r;
  r.method = "mine";
  verify::FamilyCheck f;
  f.family = "tritri_shared_edge";
  f.kind = io::Kind::tritri;
  f.stats.cases = 40;
  f.stats.false_hit = 3;
  f.stats.false_miss = 5;
  f.stats.unjudged = 2;
  r.families.push_back(f);
  r.promises.push_back({"no-false-negative", false, 5});
  const auto table = verify::check_table(r);
  EXPECT_NE(table.find("false meets"), std::string::npos) << table;
  EXPECT_NE(table.find("false disjoint"), std::string::npos) << table;
  {  // the row: cases, false meets, false disjoint, wrong class, no t (three "-"), no tolerance ("-"), failures
    std::istringstream row(table.substr(table.find("tritri_shared_edge")));
    std::vector<std::string> cells(10);
    for (auto& c : cells) row >> c;
    EXPECT_EQ(cells, (std::vector<std::string>{"tritri_shared_edge", "40", "3", "5", "0", "-", "-", "-", "-", "0"})) << table;
  }
  const auto s = verify::check_sentences(r);
  ASSERT_GE(s.size(), 3u);
  EXPECT_EQ(s[0], "8 of 40 pairs (20%) have a class error: 3 false meets (disjoint, called meeting), "
                  "5 false disjoints (meeting, called disjoint), 0 wrong classes.");
  EXPECT_EQ(s[1], "2 pairs answered meets-or-not whose exact class is degenerate or invalid are not judged.");
  EXPECT_EQ(s[2], "Promise no-false-negative: BROKEN by 5 pairs (false disjoints and failures).");
  // A ray family among them: the ray words.
  verify::FamilyCheck g;
  g.family = "tri_edge";
  g.kind = io::Kind::triangle;
  g.stats.cases = 10;
  r.families.push_back(g);
  EXPECT_NE(verify::check_table(r).find("false hit"), std::string::npos);
  EXPECT_EQ(verify::check_sentences(r)[0].find("8 of 50 cases"), 0u);
}

}  // namespace
}  // namespace rayproof
