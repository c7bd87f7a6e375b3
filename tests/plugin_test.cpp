// Plugins (rayproof/plugin.h, --plugin) and the example kernels (examples/): the loader's checks and
// messages, in-process plugins against the built-in methods and exact, the plugin host (the line
// protocol), forked plugins (an --exec kernel running the host: a crash is a kernel failure), and
// the naive Möller–Trumbore examples in C, Python and JavaScript caught on exact edge and vertex hits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/user_kernels.h"
#include "cli_support.h"
#include "stats_support.h"
#include "gen/families.h"
#include "io/case_file.h"
#include "methods/plugin_kernel.h"
#include "verify/differential.h"

namespace rayproof {
namespace {

using testing::run_rayproof;
using testing::expect_same_tallies;
using testing::scratch_dir;
using testing::slurp;

Method load_ok(const std::string& path, const std::string& name = "") {
  auto r = load_plugin_method(path, name);
  if (auto* why = std::get_if<std::string>(&r)) {
    ADD_FAILURE() << *why;
    return {};
  }
  return std::get<Method>(r);
}

std::string load_error(const std::string& path) {
  auto r = load_plugin_method(path);
  if (std::holds_alternative<Method>(r)) return "(loaded)";
  return std::get<std::string>(r);
}

std::vector<io::Case> cases_of(const std::string& family, std::size_t n, std::uint64_t seed = 1) {
  const gen::Family* f = gen::find_family(family);
  if (!f) {
    ADD_FAILURE() << "no family " << family;
    return {};
  }
  return gen::generate(*f, n, seed, gen::Precision::float64);
}

/// Every family of rays (not the tritri_* pair families), n cases each.
std::vector<io::Case> all_families(std::size_t n) {
  std::vector<io::Case> all;
  for (const auto& f : gen::families()) {
    if (f.kind == io::Kind::tritri) continue;
    auto c = gen::generate(f, n, 7, gen::Precision::float64);
    all.insert(all.end(), c.begin(), c.end());
  }
  return all;
}

// --- the header ----------------------------------------------------------------------------------

TEST(PluginHeader, AbiVersionAndClassNumbersMatchTheLibrary) {
  EXPECT_EQ(RAYPROOF_PLUGIN_ABI_VERSION, 1);
  for (std::size_t i = 0; i < io::kAllKinds.size(); ++i)
    EXPECT_EQ(static_cast<int>(io::kAllKinds[i]), static_cast<int>(i));
  EXPECT_EQ(RAYPROOF_KIND_TRIANGLE, static_cast<int>(io::Kind::triangle));
  EXPECT_EQ(RAYPROOF_KIND_DISK, static_cast<int>(io::Kind::disk));
  EXPECT_EQ(RAYPROOF_INVALID, static_cast<int>(Contact::invalid));
  EXPECT_EQ(RAYPROOF_COPLANAR, static_cast<int>(Contact::coplanar));
  EXPECT_EQ(RAYPROOF_HIT, static_cast<int>(Contact::hit));
  EXPECT_EQ(RAYPROOF_RIM, static_cast<int>(Contact::rim));
  EXPECT_EQ(RAYPROOF_RIM + 1, static_cast<int>(Contact::error));
}

// --- answers ---------------------------------------------------------------------------------------

TEST(PluginAnswer, FullAndCoarseAnswersBecomeResults) {
  rayproof_answer a{RAYPROOF_EDGE, RAYPROOF_HAS_T, 2.5, 0, 0, 0};
  auto r = plugin_answer_to_result(io::Kind::triangle, a);
  ASSERT_TRUE(std::holds_alternative<io::CaseResult>(r));
  EXPECT_EQ(io::format_answer(std::get<io::CaseResult>(r)), "edge 2.5 -");

  a = {RAYPROOF_COARSE_HIT, RAYPROOF_HAS_T | RAYPROOF_HAS_B, 1.0, 0, 0.25, 0.5};
  r = plugin_answer_to_result(io::Kind::triangle, a);
  ASSERT_TRUE(std::holds_alternative<io::CaseResult>(r));
  EXPECT_EQ(std::get<io::CaseResult>(r).form, io::AnswerForm::coarse);
  EXPECT_EQ(io::format_answer(std::get<io::CaseResult>(r)), "hit 1.0 0.25 0.5");

  a = {RAYPROOF_COARSE_HIT, 0, 0, 0, 0, 0};
  r = plugin_answer_to_result(io::Kind::sphere, a);
  ASSERT_TRUE(std::holds_alternative<io::CaseResult>(r));
  EXPECT_EQ(io::format_answer(std::get<io::CaseResult>(r)), "hit");

  a = {RAYPROOF_COARSE_MISS, 0, 0, 0, 0, 0};
  r = plugin_answer_to_result(io::Kind::box, a);
  ASSERT_TRUE(std::holds_alternative<io::CaseResult>(r));
  EXPECT_EQ(io::format_answer(std::get<io::CaseResult>(r)), "miss");
}

TEST(PluginAnswer, AnswersOutsideTheVocabularyAreFailures) {
  const std::vector<std::pair<rayproof_answer, io::Kind>> bad = {
      {{RAYPROOF_NO_ANSWER, 0, 0, 0, 0, 0}, io::Kind::triangle},                      // nothing written
      {{99, 0, 0, 0, 0, 0}, io::Kind::triangle},                                      // unknown class
      {{14, 0, 0, 0, 0, 0}, io::Kind::triangle},                                      // `error` is no class
      {{RAYPROOF_HIT, 8, 0, 0, 0, 0}, io::Kind::sphere},                              // unknown bit
      {{RAYPROOF_EDGE, RAYPROOF_HAS_T | RAYPROOF_HAS_B, 1, 0, 0, 0}, io::Kind::triangle},  // b on full
      {{RAYPROOF_COARSE_MISS, RAYPROOF_HAS_T, 1, 0, 0, 0}, io::Kind::triangle},      // miss with t
      {{RAYPROOF_COARSE_HIT, RAYPROOF_HAS_T2, 0, 1, 0, 0}, io::Kind::sphere},        // t2 on coarse
      {{RAYPROOF_COARSE_HIT, RAYPROOF_HAS_B, 0, 0, 0, 0}, io::Kind::triangle},       // b without t
      {{RAYPROOF_COARSE_HIT, RAYPROOF_HAS_T | RAYPROOF_HAS_B, 1, 0, 0, 0}, io::Kind::disk},  // b on a disk
  };
  for (const auto& [a, kind] : bad) {
    const auto r = plugin_answer_to_result(kind, a);
    ASSERT_TRUE(std::holds_alternative<std::string>(r)) << "class " << a.cls << " has " << a.has;
    EXPECT_FALSE(std::get<std::string>(r).empty());
  }
}

// --- the loader's checks -----------------------------------------------------------------------------

TEST(PluginLoader, MissingFileNotALibraryNoEntryWrongVersionBadDeclaration) {
  EXPECT_NE(load_error("/nonexistent/mine.so").find("no such file"), std::string::npos);
  const auto text = testing::write_file("not_a_library.so", "just text\n");
  const std::string e_text = load_error(text.string());
  EXPECT_NE(e_text.find("cannot load it as a shared library"), std::string::npos) << e_text;

  const std::string e_entry = load_error(PLUGIN_NO_ENTRY);
  EXPECT_NE(e_entry.find("no entry point rayproof_plugin_entry"), std::string::npos) << e_entry;
  const std::string e_version = load_error(PLUGIN_WRONG_VERSION);
  EXPECT_NE(e_version.find("built for plugin ABI version 2, this rayproof loads version 1"), std::string::npos)
      << e_version;
  const std::string e_kind = load_error(PLUGIN_BAD_KIND);
  EXPECT_NE(e_kind.find("bad kind 7"), std::string::npos) << e_kind;
  const std::string e_precision = load_error(PLUGIN_BAD_PRECISION);
  EXPECT_NE(e_precision.find("kind sphere has no on_float function"), std::string::npos) << e_precision;
}

TEST(PluginLoader, DeclarationAndNameOverride) {
  const Method own = load_ok(PLUGIN_MT_C);
  EXPECT_EQ(own.name, "mt-c");
  EXPECT_EQ(own.precision, Precision::float64);
  EXPECT_EQ(own.kinds, std::vector<io::Kind>{io::Kind::triangle});
  EXPECT_EQ(load_ok(PLUGIN_MT_C, "mine").name, "mine");
  const Method f = load_ok(PLUGIN_FLOAT);
  EXPECT_EQ(f.name, "plugin-float");
  EXPECT_EQ(f.precision, Precision::float32);
  EXPECT_EQ(f.kinds.size(), 6u);
}

TEST(PluginLoader, AnswerOutsideTheVocabularyIsAKernelFailureWithTheCase) {
  const Method m = load_ok(PLUGIN_BAD_ANSWER);
  ASSERT_TRUE(m.take_failures);
  io::Case good;
  good.kind = io::Kind::triangle;
  good.v = {1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  io::Case bad = good;
  bad.v[0] = -1;
  EXPECT_EQ(m.classify(good).contact, Contact::miss);
  EXPECT_TRUE(m.take_failures().empty());
  EXPECT_EQ(m.classify(bad).contact, Contact::error);
  EXPECT_EQ(m.classify(good).contact, Contact::miss);
  const auto failures = m.take_failures();
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_NE(failures[0].what.find("unknown class 99"), std::string::npos) << failures[0].what;
  EXPECT_EQ(io::format_case(failures[0].input), io::format_case(bad));
  EXPECT_TRUE(m.take_failures().empty());
}

// --- the command line: --plugin on verify, report, fuzz ------------------------------------------------

TEST(PluginOption, OneLibraryPerOptionCaseFilesStayPositional) {
  CLI::App app;
  cli::UserKernelOptions opt;
  std::vector<std::string> files;
  cli::add_user_kernel_options(app, opt);
  app.add_option("files", files);
  app.parse("--plugin a.so --plugin mine=b.so a.txt b.txt", false);
  EXPECT_EQ(opt.plugin, (std::vector<std::string>{"a.so", "mine=b.so"}));
  EXPECT_EQ(files, (std::vector<std::string>{"a.txt", "b.txt"}));
}

TEST(PluginOption, MakeUserKernelsLoadsNamesAndRefuses) {
  cli::UserKernelOptions opt;
  opt.plugin = {PLUGIN_MT_C, std::string("mine=") + PLUGIN_MT_C};
  auto made = cli::make_user_kernels("verify", opt);
  ASSERT_TRUE(made.has_value());
  ASSERT_EQ(made->size(), 2u);
  EXPECT_EQ((*made)[0]->name, "mt-c");
  EXPECT_EQ((*made)[1]->name, "mine");
  // A name taken by a built-in method or by another kernel, an empty name, a bad library: nothing.
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{std::string("double=") + PLUGIN_MT_C},
        std::vector<std::string>{PLUGIN_MT_C, PLUGIN_MT_C}, std::vector<std::string>{std::string("=") + PLUGIN_MT_C},
        std::vector<std::string>{PLUGIN_NO_ENTRY}}) {
    opt.plugin = bad;
    EXPECT_FALSE(cli::make_user_kernels("verify", opt).has_value()) << bad.back();
  }
}

TEST(PluginOption, VerifyJsonJudgesPluginsLikeBuiltInMethods) {
  // Case files from `rayproof gen`, as a user would make them.
  std::string files;
  for (const std::string family : {"tri_edge", "tri_vertex", "sph_tangent_exact", "box_graze"}) {
    const auto g = run_rayproof("gen " + family + " -n 100 -s 3");
    ASSERT_EQ(g.status, 0) << g.err;
    files += " " + testing::write_file(family + ".txt", g.out).string();
  }
  const auto r = run_rayproof(std::string("verify --json --methods float --plugin ") + PLUGIN_FLOAT + " --plugin " +
                              PLUGIN_MT_C + " --plugin " + PLUGIN_CERTIFIED + " --" + files);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  std::map<std::pair<std::string, std::string>, nlohmann::json> rows;
  for (const auto& row : j["rows"]) rows[{row["method"], row["family"]}] = row;
  for (const std::string family : {"tri_edge", "tri_vertex", "sph_tangent_exact", "box_graze"}) {
    auto f = rows.at({"float", family}), p = rows.at({"plugin-float", family});
    f.erase("method"), p.erase("method");
    EXPECT_EQ(f, p) << family;  // the same tallies, column for column
    const auto& c = rows.at({"plugin-certified", family});
    EXPECT_EQ(c["cases"], 100) << family;
    EXPECT_EQ(c["class_errors"], 0) << family;
    EXPECT_LE(c["ulp_max"].get<std::uint64_t>(), 1u) << family;
  }
  EXPECT_GT(rows.at({"float", "box_graze"})["class_errors"].get<int>(), 0);  // the comparison is not vacuous
  for (const std::string family : {"tri_edge", "tri_vertex"}) {
    const auto& m = rows.at({"mt-c", family});
    EXPECT_EQ(m["coarse"], 100) << family;
    EXPECT_GT(m["false_miss"].get<int>(), 0) << family;
    EXPECT_EQ(m["false_hit"], 0) << family;
    EXPECT_EQ(m["kernel_failures"], 0) << family;
  }
  EXPECT_EQ(rows.count({"mt-c", "box_graze"}), 0u);  // triangles only
}

TEST(PluginOption, MethodsNamesAPluginLikeABuiltInMethod) {
  // `--methods mine` with `--plugin mine=...` runs the plugin alone.
  const auto g = run_rayproof("gen tri_edge -n 30 -s 5");
  ASSERT_EQ(g.status, 0) << g.err;
  const auto file = testing::write_file("plugin_methods.txt", g.out).string();
  auto r = run_rayproof(std::string("verify --json --methods mine --plugin mine=") + PLUGIN_MT_C + " -- " + file);
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["rows"].size(), 1u) << r.out;
  EXPECT_EQ(j["rows"][0]["method"], "mine");
  EXPECT_EQ(j["rows"][0]["cases"], 30);
  r = run_rayproof(std::string("verify --methods mine,nosuch --plugin mine=") + PLUGIN_MT_C + " -- " + file);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown method 'nosuch'"), std::string::npos) << r.err;
}

// --- plugins against the built-in methods and exact ----------------------------------------------------

TEST(PluginMethods, FloatPluginGivesTheBuiltInFloatTallies) {
  MethodRegistry reg;
  register_fast_methods(reg);
  const Method* builtin = reg.find("float");
  ASSERT_NE(builtin, nullptr);
  const Method plugin = load_ok(PLUGIN_FLOAT);
  const auto cases = all_families(40);
  const auto exact = verify::exact_answers(cases);
  const auto cmp = verify::compare(cases, exact, {builtin, &plugin}, 0);
  const auto ray_families = static_cast<std::size_t>(std::count_if(
      gen::families().begin(), gen::families().end(), [](const gen::Family& f) { return f.kind != io::Kind::tritri; }));
  ASSERT_EQ(cmp.groups.size(), ray_families);  // the pair families are not run: float answers rays
  for (const auto& g : cmp.groups) {
    const auto a = cmp.stats.find({"float", g}), b = cmp.stats.find({"plugin-float", g});
    ASSERT_TRUE(a != cmp.stats.end() && b != cmp.stats.end()) << g;
    expect_same_tallies(a->second, b->second, g);
  }
  // Not vacuous: the float method does make class errors on these families.
  EXPECT_GT(cmp.total("float").class_errors(), 0u);
  // And answer for answer (as text: a NaN t is not equal to itself).
  for (const auto& c : cases)
    EXPECT_EQ(io::format_answer(plugin.run(c)), io::format_answer(builtin->run(c))) << io::format_case(c);
}

TEST(PluginMethods, CertifiedPluginAgreesWithExactEverywhere) {
  const Method plugin = load_ok(PLUGIN_CERTIFIED);
  const auto cases = all_families(40);
  const auto exact = verify::exact_answers(cases);
  const auto cmp = verify::compare(cases, exact, {&plugin}, 0);
  const auto total = cmp.total("plugin-certified");
  EXPECT_EQ(total.cases, cases.size());
  EXPECT_EQ(total.class_errors(), 0u);
  EXPECT_LE(total.ulp_quantile(1.0), 1u);
}

TEST(PluginMethods, NaiveCPluginHasFalseMissesOnEdgesAndVertices) {
  const Method plugin = load_ok(PLUGIN_MT_C);
  for (const std::string family : {"tri_edge", "tri_vertex"}) {
    const auto cases = cases_of(family, 200);
    const auto cmp = verify::compare(cases, verify::exact_answers(cases), {&plugin}, 0);
    const auto s = cmp.total("mt-c");
    EXPECT_EQ(s.cases, 200u) << family;
    EXPECT_GT(s.false_miss, 0u) << family;
    EXPECT_LT(s.false_miss, s.cases) << family;  // it does hit the others
    EXPECT_EQ(s.false_hit, 0u) << family;        // every case touches
  }
}

// --- the line protocol: the plugin host and the Python / JavaScript examples -------------------------

std::string case_text(const std::vector<io::Case>& cases) {
  std::string s;
  for (const auto& c : cases) s += io::format_case(c) + "\n";
  return s;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

/// Runs a shell command with `input` on its standard input; its standard output, and its status.
std::pair<std::string, int> run_shell(const std::string& command, const std::string& input) {
  const auto dir = scratch_dir();
  const auto in = dir / "shell_in.txt", out = dir / "shell_out.txt";
  std::ofstream(in, std::ios::binary) << input;
  const int raw = std::system((command + " <" + in.string() + " >" + out.string() + " 2>/dev/null").c_str());
  const int status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  return {slurp(out), status};
}

/// A coarse answer line (`miss`, `hit T B1 B2`), as the examples print them.
std::optional<io::CaseResult> parse_coarse(const std::string& line) {
  std::istringstream in(line);
  std::string word;
  in >> word;
  io::CaseResult r;
  r.form = io::AnswerForm::coarse;
  if (word == "miss") {
    r.contact = Contact::miss;
    return r;
  }
  if (word != "hit") return std::nullopt;
  r.contact = Contact::hit;
  std::string t, b1, b2;
  if (!(in >> t >> b1 >> b2)) return std::nullopt;
  r.t = std::strtod(t.c_str(), nullptr), r.b1 = std::strtod(b1.c_str(), nullptr), r.b2 = std::strtod(b2.c_str(), nullptr);
  return r;
}

const std::string kExamples = RAYPROOF_SOURCE_DIR "/examples";

TEST(ProtocolExamples, PythonAndJavaScriptHaveFalseMissesOnEdgesAndVertices) {
  // Through --exec's method (methods/exec_kernel.h) and the differential comparison verify runs.
  const std::vector<std::string> specs = {"mt-python=python3 " + kExamples + "/python/moller_trumbore.py",
                                          "mt-js=node " + kExamples + "/js/moller_trumbore.js"};
  for (const auto& spec : specs) {
    auto made = make_exec_method(spec);
    ASSERT_TRUE(std::holds_alternative<Method>(made)) << std::get<std::string>(made);
    const Method& m = std::get<Method>(made);
    EXPECT_EQ(m.precision, Precision::float64);
    EXPECT_EQ(m.kinds, std::vector<io::Kind>{io::Kind::triangle});
    for (const std::string family : {"tri_edge", "tri_vertex"}) {
      const auto cases = cases_of(family, 100);
      const auto cmp = verify::compare(cases, verify::exact_answers(cases), {&m}, 0);
      const auto s = cmp.total(m.name);
      EXPECT_EQ(s.cases, cases.size()) << spec << " " << family;
      EXPECT_EQ(s.coarse, cases.size()) << spec << " " << family;
      EXPECT_EQ(s.kernel_failures, 0u) << spec << " " << family;
      EXPECT_GT(s.false_miss, 0u) << spec << " " << family;
      EXPECT_LT(s.false_miss, cases.size()) << spec << " " << family;
      EXPECT_EQ(s.false_hit, 0u) << spec << " " << family;  // every case touches
      EXPECT_TRUE(m.take_failures().empty());
    }
  }
}

TEST(ProtocolExamples, PythonJavaScriptAndCPluginAnswerAlike) {
  // The same double arithmetic in the same order: the same answers, line for line.
  auto cases = cases_of("tri_generic", 100);
  const auto edge = cases_of("tri_edge", 50);
  cases.insert(cases.end(), edge.begin(), edge.end());
  io::Case inf_case = cases[0];
  inf_case.v[0] = std::numeric_limits<double>::infinity();
  io::Case nan_case = cases[1];
  nan_case.v[4] = std::numeric_limits<double>::quiet_NaN();
  cases.push_back(inf_case);
  cases.push_back(nan_case);
  // A case file's comment and blank lines get no answer.
  const std::string input = "# family mixed\n\n" + case_text(cases);
  const auto py = lines_of(run_shell("python3 " + kExamples + "/python/moller_trumbore.py", input).first);
  const auto js = lines_of(run_shell("node " + kExamples + "/js/moller_trumbore.js", input).first);
  const Method c_plugin = load_ok(PLUGIN_MT_C);
  ASSERT_EQ(py.size(), cases.size() + 1);
  ASSERT_EQ(js.size(), cases.size() + 1);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const auto p = parse_coarse(py[i + 1]), j = parse_coarse(js[i + 1]);
    ASSERT_TRUE(p && j) << py[i + 1] << " / " << js[i + 1];
    const io::CaseResult c = c_plugin.run(cases[i]);
    EXPECT_EQ(*p, c) << io::format_case(cases[i]) << ": python " << py[i + 1];
    // JavaScript prints -0 as 0: compare values, not signs of zero.
    EXPECT_EQ(j->contact, c.contact) << io::format_case(cases[i]) << ": js " << js[i + 1];
    EXPECT_EQ(j->t, c.t) << io::format_case(cases[i]);
    EXPECT_EQ(j->b1, c.b1) << io::format_case(cases[i]);
    EXPECT_EQ(j->b2, c.b2) << io::format_case(cases[i]);
  }
  EXPECT_EQ(py[cases.size() - 1], "miss");  // the inf origin
  EXPECT_EQ(py[cases.size()], "miss");      // the nan direction
}

TEST(PluginHost, ServesThePluginsAnswersOverTheProtocol) {
  auto cases = cases_of("tri_edge", 30);
  const auto generic = cases_of("tri_generic", 30);
  cases.insert(cases.end(), generic.begin(), generic.end());
  const auto r = run_rayproof(std::string("plugin-host ") + PLUGIN_MT_C, "# comment\n" + case_text(cases));
  EXPECT_EQ(r.status, 0) << r.err;
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), cases.size() + 1);
  EXPECT_EQ(lines[0], "rayproof-kernel 1 double triangle");
  const Method m = load_ok(PLUGIN_MT_C);
  for (std::size_t i = 0; i < cases.size(); ++i) EXPECT_EQ(lines[i + 1], io::format_answer(m.run(cases[i])));

  // A float plugin: full answers on float-rounded inputs, as the built-in float method gives them.
  const auto spheres = cases_of("sph_generic", 20);
  const auto f = run_rayproof(std::string("plugin-host ") + PLUGIN_FLOAT, case_text(spheres));
  const auto flines = lines_of(f.out);
  ASSERT_EQ(flines.size(), spheres.size() + 1);
  EXPECT_EQ(flines[0], "rayproof-kernel 1 float plane,sphere,ellipsoid,triangle,box,disk");
  MethodRegistry reg;
  register_fast_methods(reg);
  for (std::size_t i = 0; i < spheres.size(); ++i)
    EXPECT_EQ(flines[i + 1], io::format_result(reg.find("float")->run(spheres[i])));
}

TEST(PluginHost, BadPluginsBadAnswersAndCrashes) {
  const auto missing = run_rayproof("plugin-host /nonexistent/mine.so");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("rayproof plugin-host: plugin /nonexistent/mine.so: no such file"), std::string::npos)
      << missing.err;
  const auto version = run_rayproof(std::string("plugin-host ") + PLUGIN_WRONG_VERSION);
  EXPECT_EQ(version.status, 2);
  EXPECT_NE(version.err.find("plugin ABI version 2"), std::string::npos) << version.err;

  // An answer outside the vocabulary: a line that is no answer, naming the problem.
  const std::string good = "triangle 1 0 0 0 0 1 0 0 0 1 0 0 0 1 0\n", bad = "triangle -1 0 0 0 0 1 0 0 0 1 0 0 0 1 0\n";
  const auto answer = run_rayproof(std::string("plugin-host ") + PLUGIN_BAD_ANSWER, good + bad + good);
  EXPECT_EQ(answer.status, 0);
  EXPECT_EQ(lines_of(answer.out), (std::vector<std::string>{"rayproof-kernel 1 double triangle", "miss",
                                                            "kernel-failure: answer outside the vocabulary: unknown class 99",
                                                            "miss"}));

  // A crash takes the host down (in its own process), after the declaration.
  const auto crash = run_rayproof(std::string("plugin-host ") + PLUGIN_CRASH, good + bad + good);
  EXPECT_EQ(crash.status, 128 + SIGABRT);
  EXPECT_EQ(lines_of(crash.out).at(0), "rayproof-kernel 1 double triangle");
}

// --- forked plugins: an --exec kernel running `rayproof plugin-host PATH` -------------------------------

TEST(ForkedPlugin, SameAnswersAsInProcess) {
  auto made = make_forked_plugin_method(PLUGIN_MT_C, "", RAYPROOF_BIN);
  ASSERT_TRUE(std::holds_alternative<Method>(made)) << std::get<std::string>(made);
  const Method& forked = std::get<Method>(made);
  EXPECT_EQ(forked.name, "moller_trumbore_c");
  EXPECT_EQ(forked.precision, Precision::float64);
  const Method in_process = load_ok(PLUGIN_MT_C);
  auto cases = cases_of("tri_edge", 100);
  const auto generic = cases_of("tri_generic", 100);
  cases.insert(cases.end(), generic.begin(), generic.end());
  std::vector<io::CaseResult> out(cases.size());
  forked.classify_many(cases, out);
  for (std::size_t i = 0; i < cases.size(); ++i)
    EXPECT_EQ(io::format_answer(out[i]), io::format_answer(in_process.classify(cases[i]))) << io::format_case(cases[i]);
  EXPECT_TRUE(forked.take_failures().empty());
}

TEST(ForkedPlugin, CrashingKindFunctionIsAKernelFailureWithTheCase) {
  auto made = make_forked_plugin_method(PLUGIN_CRASH, "crash", RAYPROOF_BIN);
  ASSERT_TRUE(std::holds_alternative<Method>(made)) << std::get<std::string>(made);
  const Method& m = std::get<Method>(made);
  auto cases = cases_of("tri_generic", 20);
  for (auto& c : cases) c.v[0] = std::abs(c.v[0]);  // x >= 0: the plugin answers
  const std::size_t crash_at = 13;
  cases[crash_at].v[0] = -1;  // x < 0: the plugin aborts
  std::vector<io::CaseResult> out(cases.size());
  m.classify_many(cases, out);
  for (std::size_t i = 0; i < cases.size(); ++i)
    EXPECT_EQ(out[i].contact, i == crash_at ? Contact::error : Contact::miss) << i;
  const auto failures = m.take_failures();
  ASSERT_EQ(failures.size(), 1u);
  EXPECT_NE(failures[0].what.find("crashed (signal 6"), std::string::npos) << failures[0].what;
  EXPECT_EQ(io::format_case(failures[0].input), io::format_case(cases[crash_at]));
}

TEST(ForkedPlugin, BadPluginsAreRefusedWithTheHostsMessage) {
  const auto missing = make_forked_plugin_method("/nonexistent/mine.so", "mine", RAYPROOF_BIN);
  ASSERT_TRUE(std::holds_alternative<std::string>(missing));
  EXPECT_NE(std::get<std::string>(missing).find("no such file"), std::string::npos) << std::get<std::string>(missing);
  const auto version = make_forked_plugin_method(PLUGIN_WRONG_VERSION, "future", RAYPROOF_BIN);
  ASSERT_TRUE(std::holds_alternative<std::string>(version));
  EXPECT_NE(std::get<std::string>(version).find("plugin ABI version 2"), std::string::npos)
      << std::get<std::string>(version);
}

}  // namespace
}  // namespace rayproof
