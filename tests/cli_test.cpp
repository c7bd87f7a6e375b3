// The command-line tool as a user runs it: outputs, messages and exit statuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.h"

using rayproof::testing::run_rayproof;
using rayproof::testing::slurp;
using rayproof::testing::write_file;

namespace {
const std::string kData = RAYPROOF_DATA_DIR;
}

TEST(Cli, ClassifyDoubleAnswersTheWorkedExamples) {
  const auto r = run_rayproof("classify --method double " + kData + "/worked_examples.txt");
  EXPECT_EQ(r.status, 0) << r.err;
  const std::string want = slurp(kData + "/worked_examples.expected");
  // Classes must match exactly; the t values are checked to 4 ulps in methods_test.
  std::istringstream a(r.out), b(want);
  std::string la, lb;
  int n = 0;
  while (std::getline(b, lb)) {
    ASSERT_TRUE(std::getline(a, la));
    EXPECT_EQ(la.substr(0, la.find(' ')), lb.substr(0, lb.find(' '))) << "line " << n;
    ++n;
  }
  EXPECT_EQ(n, 17);
}

TEST(Cli, ExactMatchesTheIndependentAnswersBitForBit) {
  for (const char* stem : {"worked_examples", "sample"}) {
    const auto r = run_rayproof(std::string("classify --method exact ") + kData + "/" + stem + ".txt");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out, slurp(kData + "/" + stem + ".expected")) << stem;
  }
}

TEST(Cli, MalformedLineIsNamedAndTheRestAnswered) {
  const auto f = write_file("bad.txt", "plane 0 0 0 0 0 2 0 0 5 0 0 1\nsphere 1 2 3\nplane 0 0 0 0 0 -1 0 0 5 0 0 1\n");
  const auto r = run_rayproof("classify " + f.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out, "hit 2.5 -\nerror - -\nbehind -5.0 -\n");
  EXPECT_NE(r.err.find(f.string() + ":2: sphere needs 10 numbers, got 3"), std::string::npos) << r.err;
}

TEST(Cli, MissingFileAndEmptyFileAreErrors) {
  auto r = run_rayproof("classify /nonexistent/cases.txt");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/nonexistent/cases.txt: no such file"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  const auto empty = write_file("empty.txt", "");
  r = run_rayproof("classify " + empty.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no cases"), std::string::npos) << r.err;
  r = run_rayproof("classify " + rayproof::testing::scratch_dir().string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
}

TEST(Cli, StandardInputAndInvalidValues) {
  const auto r = run_rayproof("classify --method float -", "sphere 0 0 0 nan 0 1 0 0 5 1\nbox 0 0 0 1 1 1 1 1 1 0 2 2\n");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "invalid - -\ninvalid - -\n");
}

TEST(Cli, UnknownMethodIsRefused) {
  const auto r = run_rayproof("classify --method nope " + kData + "/worked_examples.txt");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown method 'nope'"), std::string::npos);
}

// One executable holds every command: a lone copy of it, with nothing beside it, lists and runs
// the scene commands and the --mesh modes of check, fuzz and spawn as well as the case-level ones.
TEST(Cli, EveryCommandRunsFromTheOneExecutableAlone) {
  namespace fs = std::filesystem;
  const fs::path dir = rayproof::testing::scratch_dir() / "alone";
  fs::create_directories(dir);
  fs::copy_file(RAYPROOF_BIN, dir / "rayproof", fs::copy_options::overwrite_existing);
  const std::string alone = (dir / "rayproof").string();
  auto run = [&](const std::string& args, const std::string& in = {}) { return rayproof::testing::run_program(alone, args, in); };
  const auto top = run("--help");
  ASSERT_EQ(top.status, 0);
  for (const char* name : {"classify", "gen", "verify", "report", "check", "fuzz", "spawn", "serve", "irradiance", "methods",
                           "cast", "render", "bench", "advise", "contains"}) {
    EXPECT_NE(top.out.find(std::string("\n  ") + name + " "), std::string::npos) << name << " not in --help:\n" << top.out;
    const auto h = run(std::string(name) + " --help");
    EXPECT_EQ(h.status, 0) << name << ": " << h.err;
    EXPECT_NE(h.out.find(alone + " " + name), std::string::npos) << name << ":\n" << h.out;
  }
  // Rays on standard input: one answer per ray.
  const auto cast = run("cast --method double default -", "0 0 -5 0 0 1\n0 0 -5 1 0 0\n");
  ASSERT_EQ(cast.status, 0) << cast.err;
  EXPECT_EQ(std::count(cast.out.begin(), cast.out.end(), '\n'), 2) << cast.out;
  // An error in a scene command: its message and status 2.
  const auto bad = run("cast --method nope default -", "0 0 -5 0 0 1\n");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("unknown method 'nope'"), std::string::npos) << bad.err;
  const auto c = run("classify --method double " + kData + "/worked_examples.txt");
  EXPECT_EQ(c.status, 0) << c.err;
  EXPECT_FALSE(c.out.empty());
  // The mesh modes: status 0 and a line of their output.
  for (const auto& [args, line] : std::vector<std::pair<std::string, std::string>>{
           {"check --method certified --mesh generated --meshes 1 --mesh-targets 40", "rayproof check --mesh: kernel 'certified'"},
           {"fuzz --mesh --cases 1 --methods robust --seed 3", "reproduce: rayproof fuzz --mesh --seed 3 --cases 1"},
           {"spawn --mesh generated --trials 200 --magnitudes 0", "generated 2^0"}}) {
    const auto r = run(args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find(line), std::string::npos) << args << ":\n" << r.out;
  }
}
