// The command-line tool as a user runs it: outputs, messages and exit statuses.
#include <gtest/gtest.h>

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
