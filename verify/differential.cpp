#include "verify/differential.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

#include "rayproof/float_util.h"
#include "verify/exact_method.h"

namespace rayproof::verify {

bool touches(const io::CaseResult& r) {
  if (r.contact == Contact::coplanar) return r.t.has_value();
  return is_hit(r.contact);
}

Verdict judge_class(const io::CaseResult& got, const io::CaseResult& want) {
  const bool g = touches(got), w = touches(want);
  if (g && !w) return Verdict::false_hit;
  if (!g && w) return Verdict::false_miss;
  if (got.contact == want.contact) return Verdict::agree;
  return g ? Verdict::wrong_hit_class : Verdict::wrong_class;
}

namespace {
std::uint64_t ulps_one(const std::optional<double>& a, const std::optional<double>& b, Precision p) {
  if (a.has_value() != b.has_value()) return std::numeric_limits<std::uint64_t>::max();
  if (!a) return 0;
  if (p == Precision::float32) return ulp_distance(static_cast<float>(*a), static_cast<float>(*b));
  return ulp_distance(*a, *b);
}
}  // namespace

std::uint64_t t_error_ulps(const io::CaseResult& got, const io::CaseResult& want, Precision p) {
  return std::max(ulps_one(got.t, want.t, p), ulps_one(got.t2, want.t2, p));
}

std::optional<double> first_contact_t(const io::CaseResult& exact) {
  if (!touches(exact)) return std::nullopt;
  return exact.contact == Contact::inside ? exact.t2 : exact.t;
}

std::uint64_t Stats::ulp_quantile(double q) const {
  if (ulps.empty()) return 0;
  std::vector<std::uint64_t> v = ulps;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(q * double(v.size()))) - (q > 0 ? 1 : 0));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void Stats::merge(const Stats& o) {
  cases += o.cases;
  false_hit += o.false_hit;
  false_miss += o.false_miss;
  wrong_hit_class += o.wrong_hit_class;
  wrong_class += o.wrong_class;
  fallbacks += o.fallbacks;
  ulps.insert(ulps.end(), o.ulps.begin(), o.ulps.end());
  kernel_failures += o.kernel_failures;
  coarse += o.coarse;
  bary_errors.insert(bary_errors.end(), o.bary_errors.begin(), o.bary_errors.end());
  promised += o.promised;
  promise_broken += o.promise_broken;
  unjudged += o.unjudged;
  if (o.worst && (!worst || o.worst->ulps > worst->ulps)) worst = o.worst;
}

std::string promise_status(const Stats& s) {
  if (s.promised == 0) return "none made";
  if (s.promise_broken == 0) return "kept on " + std::to_string(s.promised);
  return "broken on " + std::to_string(s.promise_broken) + " of " + std::to_string(s.promised);
}

bool breaks_promise(const Promise& p, Verdict v, std::uint64_t ulps, const io::CaseResult& want) {
  switch (v) {
    case Verdict::kernel_failure: return false;
    case Verdict::agree: return p.t_ulps && ulps > *p.t_ulps;
    case Verdict::false_miss:
      if (p.exact_class || p.no_false_miss == Promise::NoFalseMiss::all) return true;
      if (p.no_false_miss == Promise::NoFalseMiss::ahead) {
        const auto t = first_contact_t(want);
        return want.contact != Contact::coplanar && t && *t > 0;
      }
      return false;
    default: return p.exact_class;
  }
}

Stats Comparison::total(const std::string& method) const {
  Stats s;
  for (const auto& g : groups) {
    auto it = stats.find({method, g});
    if (it != stats.end()) s.merge(it->second);
  }
  return s;
}

ExactAnswers exact_answers(const std::vector<io::Case>& cases) {
  ExactAnswers a;
  a.as_given.reserve(cases.size());
  a.float_rounded.reserve(cases.size());
  for (const auto& c : cases) {
    a.as_given.push_back(exact_classify(c));
    const io::Case f = io::round_to_float(c);
    const bool same = std::equal(f.v.begin(), f.v.end(), c.v.begin(), [](double x, double y) {
      return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
    });
    a.float_rounded.push_back(same ? a.as_given.back() : exact_classify(f));
  }
  return a;
}

std::string group_of(const io::Case& c) { return c.family.empty() ? std::string(io::to_string(c.kind)) : c.family; }

namespace {
void judge_answer_raw(const Method& m, Judged& j, Stats& s);
}  // namespace

void judge_answer(const Method& m, Judged& j, Stats& s) {
  if (j.input.kind == io::Kind::tritri && j.got.form == io::AnswerForm::coarse && j.got.contact != Contact::error &&
      (j.want.contact == Contact::degenerate || j.want.contact == Contact::invalid)) {
    j.verdict = Verdict::agree;
    j.ulps = 0;
    j.bary_error.reset();
    ++s.unjudged;
    return;
  }
  judge_answer_raw(m, j, s);
  const Promise p = m.promise(j.input.kind);
  if (p.any()) {
    ++s.promised;
    if (breaks_promise(p, j.verdict, j.ulps, j.want)) ++s.promise_broken;
  }
  if (j.verdict == Verdict::agree && j.ulps > 0 && (!s.worst || j.ulps > s.worst->ulps))
    s.worst = Stats::Worst{j.ulps, j.input, j.got, j.want};
}

namespace {
void judge_answer_raw(const Method& m, Judged& j, Stats& s) {
  ++s.cases;
  j.ulps = 0;
  j.bary_error.reset();
  if (m.take_failures && j.got.contact == Contact::error) {
    j.verdict = Verdict::kernel_failure;
    ++s.kernel_failures;
    return;
  }
  if (j.got.form == io::AnswerForm::coarse) {
    ++s.coarse;
    const bool g = j.got.contact == Contact::hit, w = touches(j.want);
    j.verdict = g == w ? Verdict::agree : (g ? Verdict::false_hit : Verdict::false_miss);
    if (j.verdict == Verdict::false_hit) ++s.false_hit;
    if (j.verdict == Verdict::false_miss) ++s.false_miss;
    if (j.verdict != Verdict::agree || !g) return;
    if (j.got.t) s.ulps.push_back(j.ulps = ulps_one(j.got.t, first_contact_t(j.want), m.precision));
    const bool crossing = j.want.contact == Contact::interior || j.want.contact == Contact::edge ||
                          j.want.contact == Contact::vertex;
    if ((j.got.b1 || j.got.b2) && crossing) {
      if (const auto b = exact_barycentrics(j.input)) {
        double e = 0;
        if (j.got.b1) e = std::max(e, std::isnan(*j.got.b1) ? INFINITY : std::fabs(*j.got.b1 - (*b)[0]));
        if (j.got.b2) e = std::max(e, std::isnan(*j.got.b2) ? INFINITY : std::fabs(*j.got.b2 - (*b)[1]));
        j.bary_error = e;
        s.bary_errors.push_back(e);
      }
    }
    return;
  }
  j.verdict = judge_class(j.got, j.want);
  switch (j.verdict) {
    case Verdict::false_hit: ++s.false_hit; break;
    case Verdict::false_miss: ++s.false_miss; break;
    case Verdict::wrong_hit_class: ++s.wrong_hit_class; break;
    case Verdict::wrong_class: ++s.wrong_class; break;
    case Verdict::kernel_failure: break;
    case Verdict::agree:
      if (j.want.t || j.got.t) s.ulps.push_back(j.ulps = t_error_ulps(j.got, j.want, m.precision));
      break;
  }
}

}  // namespace

Judged run_and_tally(const Method& m, const io::Case& c, const io::CaseResult& exact_as_given,
                     const io::CaseResult& exact_float_rounded, Stats& s) {
  const bool f32 = m.precision == Precision::float32;
  Judged j;
  j.input = f32 ? io::round_to_float(c) : c;
  j.want = f32 ? exact_float_rounded : exact_as_given;
  const std::uint64_t before = m.fallbacks ? m.fallbacks() : 0;
  j.got = m.classify(j.input);
  if (m.fallbacks) s.fallbacks += m.fallbacks() - before;
  judge_answer(m, j, s);
  return j;
}

Comparison compare(const std::vector<io::Case>& cases, const ExactAnswers& exact,
                   const std::vector<const Method*>& methods, std::size_t max_mismatches,
                   std::uint64_t ulp_tolerance) {
  Comparison cmp;
  std::vector<std::string> group(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    group[i] = group_of(cases[i]);
    if (std::find(cmp.groups.begin(), cmp.groups.end(), group[i]) == cmp.groups.end()) cmp.groups.push_back(group[i]);
  }
  for (const Method* m : methods) {
    cmp.methods.push_back(m->name);
    const bool f32 = m->precision == Precision::float32;
    std::vector<std::size_t> idx;
    std::vector<io::Case> inputs;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (!m->supports(cases[i].kind)) continue;
      idx.push_back(i);
      inputs.push_back(f32 ? io::round_to_float(cases[i]) : cases[i]);
    }
    std::vector<io::CaseResult> got(inputs.size());
    // One call over every case; a method that counts exact fallbacks is called once per run of
    // cases of one group, so its fallbacks land in the right group.
    for (std::size_t b = 0; b < idx.size();) {
      std::size_t e = idx.size();
      if (m->fallbacks) {
        e = b + 1;
        while (e < idx.size() && group[idx[e]] == group[idx[b]]) ++e;
      }
      const std::uint64_t before = m->fallbacks ? m->fallbacks() : 0;
      m->classify_many(std::span<const io::Case>(inputs).subspan(b, e - b), std::span<io::CaseResult>(got).subspan(b, e - b));
      if (m->fallbacks) cmp.stats[{m->name, group[idx[b]]}].fallbacks += m->fallbacks() - before;
      b = e;
    }
    std::size_t listed = 0;
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const std::size_t i = idx[k];
      Judged j;
      j.input = std::move(inputs[k]);
      j.want = f32 ? exact.float_rounded[i] : exact.as_given[i];
      j.got = got[k];
      judge_answer(*m, j, cmp.stats[{m->name, group[i]}]);
      if ((j.verdict != Verdict::agree || j.ulps > ulp_tolerance) && listed < max_mismatches) {
        cmp.mismatches.push_back({m->name, j.input, j.got, j.want, j.verdict, j.ulps});
        ++listed;
      }
    }
  }
  return cmp;
}

std::string to_string(Verdict v) {
  switch (v) {
    case Verdict::agree: return "agree";
    case Verdict::false_hit: return "false-hit";
    case Verdict::false_miss: return "false-miss";
    case Verdict::wrong_hit_class: return "wrong-hit-class";
    case Verdict::wrong_class: return "wrong-class";
    case Verdict::kernel_failure: return "kernel-failure";
  }
  return "?";
}

}  // namespace rayproof::verify
