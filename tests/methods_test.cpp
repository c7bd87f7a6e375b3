#include "methods/method.h"

#include <gtest/gtest.h>

#include <fstream>

#include "rayproof/float_util.h"

using namespace rayproof;

namespace {
std::vector<std::pair<io::Case, io::CaseResult>> load(const std::string& stem) {
  std::ifstream cin(std::string(RAYPROOF_DATA_DIR) + "/" + stem + ".txt");
  std::ifstream ein(std::string(RAYPROOF_DATA_DIR) + "/" + stem + ".expected");
  const auto entries = io::read_cases(cin);
  std::vector<std::pair<io::Case, io::CaseResult>> out;
  std::string line;
  for (const auto& e : entries) {
    std::getline(ein, line);
    out.emplace_back(std::get<io::Case>(e), *io::parse_result(line));
  }
  return out;
}
}  // namespace

TEST(Methods, DoubleReproducesEveryWorkedExample) {
  MethodRegistry reg;
  register_fast_methods(reg);
  for (const char* name : {"double", "cramer-double"}) {
    const Method* m = reg.find(name);
    ASSERT_NE(m, nullptr);
    for (const auto& [c, want] : load("worked_examples")) {
      if (!m->supports(c.kind)) continue;
      const auto got = m->run(c);
      EXPECT_EQ(got.contact, want.contact) << name << " line " << c.line;
      ASSERT_EQ(got.t.has_value(), want.t.has_value()) << name << " line " << c.line;
      ASSERT_EQ(got.t2.has_value(), want.t2.has_value()) << name << " line " << c.line;
      if (want.t) {
        EXPECT_LE(ulp_distance(*got.t, *want.t), 4u) << name << " line " << c.line;
      }
      if (want.t2) {
        EXPECT_LE(ulp_distance(*got.t2, *want.t2), 4u) << name << " line " << c.line;
      }
    }
  }
}

TEST(Methods, FastMethodsAnswerEverySampleLineWithAClass) {
  MethodRegistry reg;
  register_fast_methods(reg);
  const auto cases = load("sample");
  ASSERT_EQ(cases.size(), 602u);
  for (const auto& m : reg.all()) {
    for (const auto& [c, want] : cases) {
      if (!m.supports(c.kind)) continue;
      const auto got = m.run(c);
      EXPECT_NE(got.contact, Contact::error) << m.name << " line " << c.line;
      if (want.contact == Contact::invalid) {
        EXPECT_EQ(got.contact, Contact::invalid) << m.name << " line " << c.line;
      }
    }
  }
}

TEST(Methods, FloatMethodsSeeFloatInputs) {
  MethodRegistry reg;
  register_fast_methods(reg);
  io::Case c;
  c.kind = io::Kind::plane;
  // Origin z = 1 + 2^-30 rounds to 1 in float: the float method sees the origin on the plane.
  c.v = {0, 0, 1 + std::ldexp(1.0, -30), 1, 0, 0, 0, 0, 1, 0, 0, 1};
  EXPECT_EQ(reg.find("float")->run(c).contact, Contact::coplanar);
  EXPECT_EQ(reg.find("double")->run(c).contact, Contact::parallel);
}

TEST(Methods, RegistryRejectsDuplicatesAndUnknowns) {
  MethodRegistry reg;
  register_fast_methods(reg);
  EXPECT_EQ(reg.find("nope"), nullptr);
  EXPECT_THROW(register_fast_methods(reg), std::logic_error);
}
