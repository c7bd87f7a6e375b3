#include "verify/check.h"

#include <algorithm>
#include <tuple>

#include "verify/exact.h"
#include "verify/fuzz_campaign.h"

namespace rayproof::verify {

namespace {

/// How bad a judged answer is, worst first: a false miss (a leak in a mesh), a false hit, a wrong
/// class, then the t error.
std::tuple<int, std::uint64_t> badness(const Judged& j) {
  switch (j.verdict) {
    case Verdict::false_miss: return {4, 0};
    case Verdict::false_hit: return {3, 0};
    case Verdict::wrong_hit_class: return {2, 0};
    case Verdict::wrong_class: return {1, 0};
    case Verdict::agree: break;
  }
  return {0, j.ulps};
}

struct Candidate {
  Judged judged;
  std::size_t index = 0;  ///< position in the family's cases: ties keep generation order
};

void keep_worst(std::vector<Candidate>& v, std::size_t n) {
  std::stable_sort(v.begin(), v.end(), [](const Candidate& a, const Candidate& b) {
    const auto ba = badness(a.judged), bb = badness(b.judged);
    if (ba != bb) return ba > bb;
    return a.index < b.index;
  });
  // The float-built and double-built halves can hold the same case (as the kernel sees it): once.
  std::vector<Candidate> kept;
  for (auto& c : v) {
    if (kept.size() == n) break;
    const bool seen = std::any_of(kept.begin(), kept.end(), [&](const Candidate& k) {
      return k.judged.input.kind == c.judged.input.kind && k.judged.input.v == c.judged.input.v;
    });
    if (!seen) kept.push_back(std::move(c));
  }
  v = std::move(kept);
}

}  // namespace

bool is_watertight_family(const std::string& family) { return family == "tri_edge" || family == "tri_vertex"; }

Stats CheckResult::total() const {
  Stats s;
  for (const auto& f : families) s.merge(f.stats);
  return s;
}

std::size_t CheckResult::over_tolerance() const {
  std::size_t n = 0;
  for (const auto& f : families) n += f.over_tolerance;
  return n;
}

std::size_t CheckResult::failures() const {
  std::size_t n = 0;
  for (const auto& f : families) n += f.failures.size();
  return n;
}

bool CheckResult::promises_kept() const {
  return std::all_of(promises.begin(), promises.end(), [](const PromiseCheck& p) { return p.kept; });
}

CheckResult check(const Method& m, const CheckOptions& opt) {
  CheckResult res;
  res.method = m.name;
  res.precision = m.precision;
  res.seed = opt.seed;
  res.count = opt.count;
  res.ulp_tolerance = opt.ulp_tolerance;

  std::vector<const gen::Family*> fams = opt.families;
  if (fams.empty())
    for (const auto& f : gen::families())
      if (f.every_kind ? !m.kinds.empty() : m.supports(f.kind)) fams.push_back(&f);

  // The judgement is verify's (run_and_tally); the answers come from one classify_many per batch,
  // replayed to it through a method that returns the batch's answer for the case in hand.
  std::vector<io::CaseResult> got;
  std::size_t at = 0;
  Method replay;
  replay.name = m.name;
  replay.precision = m.precision;
  replay.kinds = m.kinds;
  replay.classify = [&](const io::Case&) { return got[at]; };

  CheckProgress progress;
  progress.families_total = fams.size();
  const bool f32 = m.precision == Precision::float32;
  const std::size_t batch = std::max<std::size_t>(opt.batch, 1);
  for (const gen::Family* f : fams) {
    FamilyCheck fc;
    fc.family = f->name;
    fc.kind = f->kind;
    std::vector<io::Case> cases;
    for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
      const std::size_t n = p == gen::Precision::float32 ? opt.count / 2 : opt.count - opt.count / 2;
      for (auto& c : gen::generate(*f, n, opt.seed, p))
        if (m.supports(c.kind)) cases.push_back(std::move(c));
    }
    const ExactAnswers exact = exact_answers(cases);
    std::vector<Candidate> worst;
    for (std::size_t b = 0; b < cases.size(); b += batch) {
      const std::size_t e = std::min(cases.size(), b + batch);
      std::vector<io::Case> seen;
      seen.reserve(e - b);
      for (std::size_t i = b; i < e; ++i) seen.push_back(f32 ? io::round_to_float(cases[i]) : cases[i]);
      got.assign(seen.size(), io::CaseResult{});
      const std::uint64_t before = m.fallbacks ? m.fallbacks() : 0;
      m.classify_many(seen, got);
      if (m.fallbacks) fc.stats.fallbacks += m.fallbacks() - before;
      if (m.take_failures)
        for (auto& kf : m.take_failures()) fc.failures.push_back(std::move(kf));
      for (std::size_t i = b; i < e; ++i) {
        at = i - b;
        Judged j = run_and_tally(replay, cases[i], exact.as_given[i], exact.float_rounded[i], fc.stats);
        if (j.verdict == Verdict::agree && j.ulps > opt.ulp_tolerance) ++fc.over_tolerance;
        if (j.verdict != Verdict::agree || j.ulps > opt.ulp_tolerance) {
          worst.push_back({std::move(j), i});
          if (worst.size() > 8 * opt.reproducers + 8) keep_worst(worst, 4 * opt.reproducers);
        }
      }
      progress.cases_done += e - b;
    }
    keep_worst(worst, opt.reproducers);
    for (auto& w : worst) {
      Reproducer r{f->name, std::move(w.judged), false};
      if (opt.minimize && r.judged.verdict != Verdict::agree) {
        const io::Case small = minimize_case(m, r.judged.input, r.judged.verdict);
        if (small.v != r.judged.input.v) {
          Stats ignored;
          r.judged = run_and_tally(m, small, exact_classify(small), exact_classify(io::round_to_float(small)), ignored);
          r.minimized = true;
        }
        // Failures on the shrunken variants are not part of the tallies.
        if (m.take_failures) (void)m.take_failures();
      }
      fc.worst.push_back(std::move(r));
    }
    res.families.push_back(std::move(fc));
    ++progress.families_done;
    progress.family = f->name;
    if (opt.progress) opt.progress(progress);
  }

  const Promises& p = opt.promises;
  if (p.watertight) {
    PromiseCheck pc{"watertight"};
    for (const auto& f : res.families)
      if (is_watertight_family(f.family)) pc.violations += f.stats.false_miss + f.failures.size();
    pc.kept = pc.violations == 0;
    res.promises.push_back(pc);
  }
  if (p.exact_class) {
    PromiseCheck pc{"exact-class"};
    for (const auto& f : res.families) pc.violations += f.stats.class_errors() + f.failures.size();
    pc.kept = pc.violations == 0;
    res.promises.push_back(pc);
  }
  if (p.max_ulps) {
    PromiseCheck pc{"max-ulps " + std::to_string(*p.max_ulps)};
    for (const auto& f : res.families)
      pc.violations += static_cast<std::size_t>(
          std::count_if(f.stats.ulps.begin(), f.stats.ulps.end(), [&](std::uint64_t u) { return u > *p.max_ulps; }));
    pc.kept = pc.violations == 0;
    res.promises.push_back(pc);
  }
  return res;
}

CheckResult check(std::function<io::CaseResult(const io::Case&)> classify, Precision precision,
                  std::vector<io::Kind> kinds, const CheckOptions& opt, std::string name) {
  Method m;
  m.name = std::move(name);
  m.precision = precision;
  m.kinds = std::move(kinds);
  m.classify = std::move(classify);
  return check(m, opt);
}

}  // namespace rayproof::verify
