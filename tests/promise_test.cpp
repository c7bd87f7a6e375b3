// Each method's declared promise (Method::promises), judged per answer and checked by fuzz.
#include <gtest/gtest.h>

#include "cli_support.h"
#include "verify/certified_method.h"
#include "verify/exact_method.h"
#include "verify/fuzz_campaign.h"

using namespace rayproof;
using verify::breaks_promise;
using verify::Verdict;

namespace {
io::CaseResult exact_hit(Contact c, double t) {
  io::CaseResult r;
  r.contact = c;
  r.t = t;
  return r;
}

MethodRegistry all_registered() {
  MethodRegistry reg;
  register_fast_methods(reg);
  verify::register_exact_method(reg);
  register_robust_methods(reg);
  verify::register_certified_method(reg);
  return reg;
}
}  // namespace

TEST(Promise, ExactClassAndUlpsBreakOnAnyClassErrorAndOnTBeyondTolerance) {
  const Promise p{true, Promise::NoFalseMiss::all, 1};
  const auto want = exact_hit(Contact::interior, 2.0);
  for (Verdict v : {Verdict::false_hit, Verdict::false_miss, Verdict::wrong_hit_class, Verdict::wrong_class})
    EXPECT_TRUE(breaks_promise(p, v, 0, want)) << verify::to_string(v);
  EXPECT_FALSE(breaks_promise(p, Verdict::agree, 1, want));
  EXPECT_TRUE(breaks_promise(p, Verdict::agree, 2, want));
  EXPECT_FALSE(breaks_promise(p, Verdict::kernel_failure, 0, want));
  EXPECT_EQ(p.describe(), "exact class, t within 1 ulp");
}

TEST(Promise, NoFalseMissAheadExceptsTheOriginOnTheSurfaceAndCoplanarRays) {
  const Promise ahead{false, Promise::NoFalseMiss::ahead, {}};
  EXPECT_TRUE(breaks_promise(ahead, Verdict::false_miss, 0, exact_hit(Contact::edge, 3.0)));
  EXPECT_FALSE(breaks_promise(ahead, Verdict::false_miss, 0, exact_hit(Contact::edge, 0.0)));
  io::CaseResult coplanar = exact_hit(Contact::coplanar, 1.5);
  coplanar.t2 = 2.5;
  EXPECT_FALSE(breaks_promise(ahead, Verdict::false_miss, 0, coplanar));
  // Only misses count: a false hit, a wrong class or any t error keep it.
  EXPECT_FALSE(breaks_promise(ahead, Verdict::false_hit, 0, exact_hit(Contact::miss, 0)));
  EXPECT_FALSE(breaks_promise(ahead, Verdict::wrong_hit_class, 0, exact_hit(Contact::edge, 3.0)));
  EXPECT_FALSE(breaks_promise(ahead, Verdict::agree, 1u << 30, exact_hit(Contact::edge, 3.0)));
  const Promise all{false, Promise::NoFalseMiss::all, {}};
  EXPECT_TRUE(breaks_promise(all, Verdict::false_miss, 0, exact_hit(Contact::edge, 0.0)));
  EXPECT_FALSE(breaks_promise(Promise{}, Verdict::false_miss, 0, exact_hit(Contact::edge, 3.0)));
  EXPECT_EQ(Promise{}.describe(), "nothing");
  EXPECT_EQ(all.describe(), "no false miss");
}

TEST(Promise, EveryMethodDeclaresWhatItPromisesPerKind) {
  const auto reg = all_registered();
  for (const char* name : {"exact", "certified"})
    for (io::Kind k : io::kAllKinds) {
      const Promise p = reg.find(name)->promise(k);
      EXPECT_TRUE(p.exact_class) << name;
      EXPECT_EQ(p.t_ulps, std::optional<std::uint64_t>(1)) << name;
    }
  const Method& robust = *reg.find("robust");
  EXPECT_EQ(robust.promise(io::Kind::triangle).no_false_miss, Promise::NoFalseMiss::ahead);
  EXPECT_EQ(robust.promise(io::Kind::box).no_false_miss, Promise::NoFalseMiss::all);
  for (io::Kind k : {io::Kind::sphere, io::Kind::ellipsoid, io::Kind::plane, io::Kind::disk})
    EXPECT_FALSE(robust.promise(k).any()) << io::to_string(k);
  for (io::Kind k : io::kAllKinds) EXPECT_FALSE(reg.find("float")->promise(k).any());
  const Method& rd = *reg.find("robust-double");
  EXPECT_EQ(rd.promise(io::Kind::box).no_false_miss, Promise::NoFalseMiss::all);
  EXPECT_FALSE(rd.promise(io::Kind::triangle).any());
}

TEST(Promise, TallyCountsPromisedCasesAndBreaks) {
  const auto reg = all_registered();
  Method liar = *reg.find("double");  // says `miss` to everything, yet promises no false miss on boxes
  liar.name = "liar";
  liar.classify = [](const io::Case&) {
    io::CaseResult r;
    r.contact = Contact::miss;
    return r;
  };
  liar.promises = {{io::Kind::box, Promise{false, Promise::NoFalseMiss::all, {}}}};
  verify::FuzzOptions opt;
  opt.methods = {reg.find("robust"), &liar};
  opt.families = {gen::find_family("box_graze"), gen::find_family("tri_edge"), gen::find_family("tri_vertex"),
                  gen::find_family("disk_rim")};
  opt.max_cases = 4000;
  opt.batch = 250;
  opt.seed = 3;
  const auto res = verify::run_fuzz(opt);
  const verify::Stats& rb = res.stats.at({"robust", "box_graze"}).counts;
  EXPECT_EQ(rb.promised, rb.cases);
  EXPECT_EQ(res.stats.at({"robust", "disk_rim"}).counts.promised, 0u);
  EXPECT_EQ(verify::promise_status(res.stats.at({"robust", "disk_rim"}).counts), "none made");
  EXPECT_EQ(verify::promise_status(rb), "kept on " + std::to_string(rb.cases));
  const verify::Stats& lb = res.stats.at({"liar", "box_graze"}).counts;
  EXPECT_GT(lb.false_miss, 0u);
  EXPECT_EQ(lb.promise_broken, lb.false_miss);
  EXPECT_EQ(res.stats.at({"liar", "tri_edge"}).counts.promised, 0u);
  EXPECT_EQ(res.broken_promises(), std::vector<std::string>{"liar"});
}

TEST(Promise, FuzzExitsNonZeroOnlyWhenADeclaredPromiseBreaks) {
  const auto dir = rayproof::testing::scratch_dir() / "promise_fuzz";
  // float makes class errors here but promises nothing; robust keeps its promises on these families.
  auto ok = rayproof::testing::run_rayproof("fuzz --methods float,robust --families box_graze,tri_edge --cases 2000 --out " +
                                            dir.string());
  EXPECT_EQ(ok.status, 0) << ok.err;
  EXPECT_NE(ok.out.find("kept on"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("none made"), std::string::npos) << ok.out;
}

TEST(Promise, ShardSummariesCarryThePromiseCountsThroughMerge) {
  const auto dir = rayproof::testing::scratch_dir() / "promise_merge";
  std::filesystem::create_directories(dir);
  std::string files;
  for (int k = 1; k <= 2; ++k) {
    const auto sum = (dir / ("s" + std::to_string(k) + ".json")).string();
    auto r = rayproof::testing::run_rayproof("fuzz --methods robust --families box_graze --cases 512 --shard " +
                                             std::to_string(k) + "/2 --summary " + sum + " --out " + dir.string());
    ASSERT_EQ(r.status, 0) << r.err;
    files += " " + sum;
  }
  auto m = rayproof::testing::run_rayproof("fuzz merge" + files);
  EXPECT_EQ(m.status, 0) << m.err;
  EXPECT_NE(m.out.find("kept on 512"), std::string::npos) << m.out;
}
