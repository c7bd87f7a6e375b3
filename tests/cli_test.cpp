// The command-line tool as a user runs it: outputs, messages and exit statuses.
#include <gtest/gtest.h>

#include <algorithm>

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

// rayproof runs the scene commands in rayproof-scene beside it (src/cli/scene_commands.h): the
// same help, the same output, status and standard input as running rayproof-scene itself.
TEST(Cli, SceneCommandsRunInRayproofSceneWithTheSameArguments) {
  namespace fs = std::filesystem;
  using rayproof::testing::run_program;
  const fs::path bin = RAYPROOF_BIN, scene = bin.parent_path() / "rayproof-scene";
  ASSERT_TRUE(fs::exists(scene)) << scene;
  const auto top = run_rayproof("--help");
  ASSERT_EQ(top.status, 0);
  for (const char* name : {"cast", "render", "bench", "advise", "contains"}) {
    EXPECT_NE(top.out.find(std::string("\n  ") + name + " "), std::string::npos) << name << " not in --help:\n" << top.out;
    const auto via = run_rayproof(std::string(name) + " --help");
    EXPECT_EQ(via.status, 0) << name << ": " << via.err;
    EXPECT_NE(via.out.find(bin.string() + " " + name + " [OPTIONS]"), std::string::npos) << name << ":\n" << via.out;
    // Its help is rayproof-scene's own, word for word but the program's name.
    auto direct = run_program(scene.string(), std::string(name) + " --help").out;
    for (std::size_t at; (at = direct.find(scene.string())) != std::string::npos;) direct.replace(at, scene.string().size(), bin.string());
    EXPECT_EQ(via.out, direct) << name;
  }
  // Rays on standard input: the answers come back through, and they are rayproof-scene's.
  const std::string rays = "0 0 -5 0 0 1\n0 0 -5 1 0 0\n";
  const auto cast = run_rayproof("cast --method double default -", rays);
  ASSERT_EQ(cast.status, 0) << cast.err;
  EXPECT_EQ(std::count(cast.out.begin(), cast.out.end(), '\n'), 2) << cast.out;
  EXPECT_EQ(cast.out, run_program(scene.string(), "cast --method double default -", rays).out);
  // An error in a forwarded command keeps its message and status.
  const auto bad = run_rayproof("cast --method nope default -", rays);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("unknown method 'nope'"), std::string::npos) << bad.err;
  // check, fuzz and spawn are rayproof's own; their --mesh modes run in rayproof-scene: status 0,
  // a line of their output, and (check, spawn: deterministic) rayproof-scene's output exactly.
  auto mesh_mode = [&](const std::string& args, const std::string& line, bool same_bytes) {
    const auto r = run_rayproof(args);
    EXPECT_EQ(r.status, 0) << args << ": " << r.err;
    EXPECT_NE(r.out.find(line), std::string::npos) << args << ":\n" << r.out;
    if (same_bytes) EXPECT_EQ(r.out, run_program(scene.string(), args).out) << args;
  };
  mesh_mode("check --method certified --mesh generated --meshes 1 --mesh-targets 40",
            "rayproof check --mesh: kernel 'certified'", true);
  mesh_mode("fuzz --mesh --cases 1 --methods robust --seed 3", "reproduce: rayproof fuzz --mesh --seed 3 --cases 1", false);
  mesh_mode("spawn --mesh generated --trials 200 --magnitudes 0", "generated 2^0", true);
}

// Without rayproof-scene (the README's first command builds only rayproof): a scene command says
// what is missing and how to build it, status 2; the case-level commands still run.
TEST(Cli, SceneCommandWithoutRayproofSceneSaysHowToBuildIt) {
  namespace fs = std::filesystem;
  const fs::path dir = rayproof::testing::scratch_dir() / "alone";
  fs::create_directories(dir);
  fs::copy_file(RAYPROOF_BIN, dir / "rayproof", fs::copy_options::overwrite_existing);
  const std::string alone = (dir / "rayproof").string();
  const auto r = rayproof::testing::run_program(alone, "cast --method double default -", "0 0 -5 0 0 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("'cast' is in " + (dir / "rayproof-scene").string() + ", which this build has not built yet"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find((dir / "rayproof-scene").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--target rayproof-scene"), std::string::npos) << r.err;
  const auto c = rayproof::testing::run_program(alone, "classify --method double " + kData + "/worked_examples.txt");
  EXPECT_EQ(c.status, 0) << c.err;
  EXPECT_FALSE(c.out.empty());
  // check and fuzz on the case families run without it; their --mesh modes say what is missing.
  const auto chk = rayproof::testing::run_program(alone, "check --method certified --families tri_edge --count 200");
  EXPECT_EQ(chk.status, 0) << chk.err;
  EXPECT_NE(chk.out.find("tri_edge"), std::string::npos) << chk.out;
  const auto fz = rayproof::testing::run_program(alone, "fuzz --cases 500 --methods double --families tri_edge --out " +
                                                            (dir / "findings").string());
  EXPECT_EQ(fz.status, 0) << fz.err;
  const auto sp = rayproof::testing::run_program(alone, "spawn --kinds plane --trials 200 --magnitudes 0");
  EXPECT_EQ(sp.status, 0) << sp.err;
  EXPECT_FALSE(sp.out.empty());
  for (const std::string mode : {"check --method certified --mesh generated", "fuzz --mesh --cases 1", "spawn --mesh generated"}) {
    const auto m = rayproof::testing::run_program(alone, mode);
    EXPECT_EQ(m.status, 2) << mode;
    const std::string head = mode.substr(0, mode.find(' '));
    EXPECT_NE(m.err.find("'" + head + " --mesh' is in "), std::string::npos) << m.err;
  }
}
