/// Stability curves (stability.h).
#include "verify/stability.h"

#include <fmt/core.h>

namespace rayproof::verify {

StabilityRun run_stability(const std::vector<const gen::Knob*>& knobs, const std::vector<const Method*>& methods,
                           std::size_t count, std::uint64_t seed,
                           const std::function<void(const std::string&)>& progress) {
  StabilityRun run;
  run.count = count;
  run.seed = seed;
  std::vector<io::Case> cases;
  std::size_t n_steps = 0;
  for (const gen::Knob* k : knobs) {
    run.knobs.push_back(k->name);
    for (int e : k->exponents) {
      auto part = gen::generate_knob(*k, e, count, seed);
      cases.insert(cases.end(), part.begin(), part.end());
      ++n_steps;
    }
  }
  if (cases.empty()) return run;
  progress(fmt::format("stability: {} knobs, {} steps x {} cases, exact answers", knobs.size(), n_steps, count));
  const ExactAnswers exact = exact_answers(cases);
  progress("stability: judging every method at every step");
  const Comparison cmp = compare(cases, exact, methods, 0);
  for (const gen::Knob* k : knobs) {
    for (const Method* m : methods) {
      if (!m->supports(k->kind)) continue;
      StabilityCurve c;
      c.knob = k->name;
      c.method = m->name;
      c.precision = m->precision;
      c.promise = m->promise(k->kind);
      for (int e : k->exponents) {
        StepTally t;
        t.exponent = e;
        if (auto it = cmp.stats.find({m->name, gen::step_name(*k, e)}); it != cmp.stats.end()) t.stats = it->second;
        t.stats.worst.reset();  // not shown; keeps the run small
        c.steps.push_back(std::move(t));
      }
      run.curves.push_back(std::move(c));
    }
  }
  return run;
}

Break find_break(const StabilityCurve& c, double class_rate, std::uint64_t ulps) {
  Break b;
  for (const auto& s : c.steps) {
    if (s.stats.cases == 0) continue;
    if (!b.class_errors && s.stats.class_error_rate() > class_rate) b.class_errors = s.exponent;
    if (!b.t_error && !s.stats.ulps.empty() && s.stats.ulp_quantile(0.5) > ulps) b.t_error = s.exponent;
  }
  return b;
}

}  // namespace rayproof::verify
