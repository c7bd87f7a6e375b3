#include "verify/check.h"

#include <algorithm>
#include <tuple>

#include "verify/exact_method.h"
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
    case Verdict::agree:
    case Verdict::kernel_failure: break;  // failures are listed apart, with the kernel's message
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

/// The method's answers on `inputs` (as it sees them), judged against exact.
std::vector<Judged> judge_all(const Method& m, const std::vector<io::Case>& inputs) {
  std::vector<io::CaseResult> got(inputs.size());
  m.classify_many(inputs, got);
  std::vector<Judged> out(inputs.size());
  Stats ignored;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    out[i].input = inputs[i];
    out[i].want = exact_classify(inputs[i]);
    out[i].got = got[i];
    judge_answer(m, out[i], ignored);
  }
  return out;
}

/// Shrinks every class-error reproducer as fuzz does (minimize_cases), all of them in lockstep so
/// that a kernel behind a pipe answers a few dozen batches, not a call per try.
void minimize_reproducers(const Method& m, CheckResult& res) {
  const bool f32 = m.precision == Precision::float32;
  std::vector<Reproducer*> todo;
  std::vector<io::Case> inputs;
  for (auto& f : res.families)
    for (auto& w : f.worst)
      if (w.judged.verdict != Verdict::agree) todo.push_back(&w), inputs.push_back(w.judged.input);
  if (todo.empty()) return;
  const auto small = minimize_cases(inputs, [&](const std::vector<io::Case>& variants, const std::vector<std::size_t>& owner) {
    std::vector<io::Case> seen;
    for (const auto& v : variants) seen.push_back(f32 ? io::round_to_float(v) : v);
    const auto judged = judge_all(m, seen);
    std::vector<bool> ok(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v)
      ok[v] = judged[v].verdict == todo[owner[v]]->judged.verdict && judged[v].input.v == variants[v].v;
    return ok;
  });
  std::vector<io::Case> changed;
  std::vector<Reproducer*> who;
  for (std::size_t k = 0; k < todo.size(); ++k)
    if (small[k].v != inputs[k].v) changed.push_back(small[k]), who.push_back(todo[k]);
  const auto final_judged = judge_all(m, changed);
  for (std::size_t k = 0; k < who.size(); ++k) {
    who[k]->judged = final_judged[k];
    who[k]->minimized = true;
  }
  // Failures on the shrunken variants are not part of the tallies.
  if (m.take_failures) (void)m.take_failures();
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

  // The answers come from one classify_many per batch; the judgement is verify's (judge_answer).
  std::vector<io::CaseResult> got;

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
        Judged j;
        j.input = std::move(seen[i - b]);
        j.want = f32 ? exact.float_rounded[i] : exact.as_given[i];
        j.got = got[i - b];
        judge_answer(m, j, fc.stats);
        if (j.verdict == Verdict::kernel_failure) continue;
        if (j.verdict == Verdict::agree && j.ulps > opt.ulp_tolerance) ++fc.over_tolerance;
        if (j.verdict != Verdict::agree || j.ulps > opt.ulp_tolerance) {
          worst.push_back({std::move(j), i});
          if (worst.size() > 8 * opt.reproducers + 8) keep_worst(worst, 4 * opt.reproducers);
        }
      }
      progress.cases_done += e - b;
    }
    keep_worst(worst, opt.reproducers);
    for (auto& w : worst) fc.worst.push_back({f->name, std::move(w.judged), false});
    res.families.push_back(std::move(fc));
    ++progress.families_done;
    progress.family = f->name;
    if (opt.progress) opt.progress(progress);
  }

  if (opt.minimize) minimize_reproducers(m, res);

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
  if (p.no_false_negative) {
    PromiseCheck pc{"no-false-negative"};
    for (const auto& f : res.families) pc.violations += f.stats.false_miss + f.failures.size();
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
