// Hostile input for every case-file command: each gets a one-line error naming the input and the
// place, a non-zero exit, no crash or hang; a good file next to a bad one is still processed.
#include <gtest/gtest.h>

#include <random>

#include "cli_support.h"

using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::write_file;

namespace {
const std::string kGood = "plane 0 0 0 0 0 2 0 0 5 0 0 1\n";

std::string garbage(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

struct Hostile {
  std::string name, path, message;
};

std::vector<Hostile> hostile_inputs() {
  const auto dir = scratch_dir();
  std::vector<Hostile> h;
  h.push_back({"empty", write_file("h_empty.txt", "").string(), "no cases"});
  h.push_back({"comments only", write_file("h_comments.txt", "# nothing\n\n").string(), "no cases"});
  h.push_back({"truncated", write_file("h_trunc.txt", "sphere 0 0 0 1 0 0 5 0 0").string(), ":1: sphere needs 10 numbers, got 9"});
  h.push_back({"truncated number", write_file("h_trunc2.txt", "plane 0 0 0 1 1 0 0 0 5 0 0 1e").string(), ":1: field 12 '1e' is not a number"});
  h.push_back({"binary garbage", write_file("h_garbage.bin", garbage(4096, 1)).string(), ":1: "});
  h.push_back({"million-char line", write_file("h_long.txt", "triangle " + std::string(1000000, '7') + "\n").string(),
               ":1: line longer than"});
  h.push_back({"directory", dir.string(), "is a directory"});
  h.push_back({"missing", (dir / "does_not_exist.txt").string(), "no such file"});
  h.push_back({"path through a file", (dir / "h_empty.txt" / "x").string(), "no such file"});
  return h;
}
}  // namespace

TEST(Hostile, ClassifyNamesInputAndPlace) {
  for (const auto& h : hostile_inputs()) {
    const auto r = run_rayproof("classify " + h.path);
    EXPECT_NE(r.status, 0) << h.name;
    EXPECT_LT(r.status, 128) << h.name << ": crashed";
    EXPECT_NE(r.err.find(h.path), std::string::npos) << h.name << ": " << r.err.substr(0, 300);
    EXPECT_NE(r.err.find(h.message), std::string::npos) << h.name << ": " << r.err.substr(0, 300);
  }
}

TEST(Hostile, VerifyNamesInputAndPlace) {
  for (const auto& h : hostile_inputs()) {
    const auto r = run_rayproof("verify --methods float " + h.path);
    EXPECT_NE(r.status, 0) << h.name;
    EXPECT_LT(r.status, 128) << h.name << ": crashed";
    EXPECT_NE(r.err.find(h.path), std::string::npos) << h.name << ": " << r.err.substr(0, 300);
  }
}

TEST(Hostile, ReportOnABadInputFile) {
  for (const auto& h : hostile_inputs()) {
    if (h.message.rfind(":1:", 0) == 0) continue;  // files with some readable structure are reported per line
    const auto r = run_rayproof("report --input " + h.path + " --out " + (scratch_dir() / "rep").string());
    EXPECT_EQ(r.status, 2) << h.name;
    EXPECT_NE(r.err.find(h.path), std::string::npos) << h.name << ": " << r.err.substr(0, 300);
  }
}

TEST(Hostile, GoodFileNextToABadOneIsStillAnswered) {
  const auto good = write_file("h_good.txt", kGood);
  const auto bad = write_file("h_bad.txt", "sphere 1 2\n");
  auto r = run_rayproof("classify " + bad.string() + " /nonexistent " + good.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "error - -\nhit 2.5 -\n");
  EXPECT_NE(r.err.find(bad.string() + ":1:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/nonexistent: no such file"), std::string::npos) << r.err;
  r = run_rayproof("verify --methods double /nonexistent " + good.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("double           plane                          1"), std::string::npos) << r.out;
}

TEST(Hostile, NanAndInfinityEverywhereAreInvalidNotErrors) {
  std::string text;
  for (const char* kind : {"plane 12", "sphere 10", "ellipsoid 12", "triangle 15", "box 12", "disk 13"}) {
    std::string k(kind);
    const int n = std::stoi(k.substr(k.find(' ') + 1));
    for (const char* v : {"nan", "inf", "-inf", "-nan"}) {
      text += k.substr(0, k.find(' '));
      for (int i = 0; i < n; ++i) text += std::string(" ") + v;
      text += "\n";
    }
  }
  const auto f = write_file("h_nan.txt", text);
  for (const char* m : {"float", "double", "exact", "robust", "certified"}) {
    const auto r = run_rayproof(std::string("classify --method ") + m + " " + f.string());
    EXPECT_EQ(r.status, 0) << m << r.err;
    std::size_t lines = 0, invalid = 0;
    for (std::size_t p = 0; (p = r.out.find('\n', p)) != std::string::npos; ++p) ++lines;
    for (std::size_t p = 0; (p = r.out.find("invalid - -", p)) != std::string::npos; ++p) ++invalid;
    EXPECT_EQ(lines, 24u) << m;
    EXPECT_EQ(invalid, 24u) << m;
  }
}

TEST(Hostile, AbsurdSizesAreRefused) {
  auto r = run_rayproof("gen tri_edge --count 100000000000");
  EXPECT_EQ(r.status, 2);
  EXPECT_LT(r.err.size(), 2000u);
  r = run_rayproof("report --count 0");
  EXPECT_NE(r.status, 0);
  r = run_rayproof("fuzz --cases 0");
  EXPECT_NE(r.status, 0);
  r = run_rayproof("gen no_such_family");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no_such_family"), std::string::npos);
}
