#include "verify/fuzz_campaign.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <ctime>
#include <cmath>
#include <mutex>
#include <optional>
#include <span>
#include <thread>

#include "verify/exact_method.h"

namespace rayproof::verify {

bool is_mismatch(const Method& m, const Judged& j) {
  if (j.verdict != Verdict::agree) return true;
  return breaks_promise(m.promise(j.input.kind), j.verdict, j.ulps, j.want);
}

std::vector<std::string> broken_promises(const std::map<std::pair<std::string, std::string>, Stats>& stats) {
  std::vector<std::string> out;
  for (const auto& [key, s] : stats)
    if (s.promise_broken > 0 && std::find(out.begin(), out.end(), key.first) == out.end()) out.push_back(key.first);
  return out;
}

std::vector<std::string> FuzzResult::broken_promises() const { return verify::broken_promises(stats); }

namespace {

std::uint64_t round_seed(std::uint64_t seed, std::size_t round) {
  // splitmix64 finalizer over (seed, round): independent, reproducible seeds per round.
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (round + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// The method's answer on one case against exact computed afresh (for minimization).
Judged judge(const Method& m, const io::Case& given) {
  Stats ignored;
  const io::CaseResult exact = exact_classify(given);
  return run_and_tally(m, given, exact, exact_classify(io::round_to_float(given)), ignored);
}

/// x rounded to `bits` significant bits (round to nearest), or x when that is not finite.
double keep_bits(double x, int bits) {
  if (x == 0 || !std::isfinite(x)) return x;
  int e;
  const double f = std::frexp(x, &e);  // x = f 2^e, 0.5 <= |f| < 1
  const double r = std::ldexp(std::nearbyint(std::ldexp(f, bits)), e - bits);
  return std::isfinite(r) ? r : x;
}

struct RoundOutput {
  std::size_t round = 0, cases = 0;
  std::map<std::pair<std::string, std::string>, Stats> stats;
  std::vector<FuzzFinding> findings;
};

RoundOutput run_round(const FuzzOptions& opt, std::size_t round) {
  RoundOutput out;
  out.round = round;
  const auto precision = round % 2 == 0 ? gen::Precision::float32 : gen::Precision::float64;
  std::vector<std::vector<io::Case>> cases;
  std::vector<ExactAnswers> exact;
  for (const gen::Family* f : opt.families) {
    cases.push_back(gen::generate(*f, opt.batch, round_seed(opt.seed, round), precision));
    out.cases += cases.back().size();
    exact.push_back(exact_answers(cases.back()));
  }
  // One classify_many call per method over the round (per family for methods that count exact
  // fallbacks, so that they land in the right family).
  for (const Method* m : opt.methods) {
    const bool f32 = m->precision == Precision::float32;
    std::vector<io::Case> inputs;
    std::vector<std::pair<std::size_t, std::size_t>> where;  // (family, case)
    std::vector<std::size_t> family_start;
    for (std::size_t fi = 0; fi < opt.families.size(); ++fi) {
      out.stats[{m->name, opt.families[fi]->name}];
      family_start.push_back(inputs.size());
      for (std::size_t i = 0; i < cases[fi].size(); ++i) {
        if (!m->supports(cases[fi][i].kind)) continue;
        inputs.push_back(f32 ? io::round_to_float(cases[fi][i]) : cases[fi][i]);
        where.emplace_back(fi, i);
      }
    }
    family_start.push_back(inputs.size());
    std::vector<io::CaseResult> got(inputs.size());
    if (m->fallbacks) {
      for (std::size_t fi = 0; fi < opt.families.size(); ++fi) {
        const std::size_t b = family_start[fi], e = family_start[fi + 1];
        const std::uint64_t before = m->fallbacks();
        m->classify_many(std::span<const io::Case>(inputs).subspan(b, e - b), std::span<io::CaseResult>(got).subspan(b, e - b));
        out.stats[{m->name, opt.families[fi]->name}].fallbacks += m->fallbacks() - before;
      }
    } else {
      m->classify_many(inputs, got);
    }
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const auto [fi, i] = where[k];
      const gen::Family* f = opt.families[fi];
      Judged j;
      j.input = std::move(inputs[k]);
      j.want = f32 ? exact[fi].float_rounded[i] : exact[fi].as_given[i];
      j.got = got[k];
      judge_answer(*m, j, out.stats[{m->name, f->name}]);
      if (is_mismatch(*m, j))
        out.findings.push_back({m->name, f->name, round, j.input, j.got, j.want, j.verdict, j.ulps, false});
    }
  }
  return out;
}

}  // namespace

std::vector<io::Case> minimize_cases(const std::vector<io::Case>& inputs, const StillFails& still) {
  std::vector<io::Case> best = inputs;
  std::vector<io::Case> variants;
  std::vector<std::size_t> owner;
  // Judges every variant in one call; returns, per input, the first variant that still fails.
  auto first_failing = [&]() {
    std::vector<std::optional<std::size_t>> pick(best.size());
    if (variants.empty()) return pick;
    const std::vector<bool> ok = still(variants, owner);
    for (std::size_t v = 0; v < variants.size(); ++v)
      if (ok[v] && !pick[owner[v]]) pick[owner[v]] = v;
    return pick;
  };
  // 1. A common power-of-two scale toward magnitude 1 keeps the geometry (and exact class) and
  //    shows the case at readable magnitudes, when it still disagrees.
  for (std::size_t k = 0; k < best.size(); ++k) {
    const int n = io::field_count(best[k].kind);
    double big = 0;
    for (int i = 0; i < n; ++i) big = std::max(big, std::fabs(best[k].v[static_cast<std::size_t>(i)]));
    if (!(big > 0) || !std::isfinite(big)) continue;
    int e;
    std::frexp(big, &e);
    if (e == 0) continue;
    io::Case scaled = best[k];
    bool exact_scale = true;
    for (int i = 0; i < n; ++i) {
      double& x = scaled.v[static_cast<std::size_t>(i)];
      const double y = std::ldexp(x, -e);
      if (std::ldexp(y, e) != x) exact_scale = false;
      x = y;
    }
    if (exact_scale) variants.push_back(scaled), owner.push_back(k);
  }
  auto pick = first_failing();
  for (std::size_t k = 0; k < best.size(); ++k)
    if (pick[k]) best[k] = variants[*pick[k]];
  // 2. Fewer significant bits per field, greedily (the fewest bits that still fail), twice over.
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i < 15; ++i) {
      variants.clear(), owner.clear();
      for (std::size_t k = 0; k < best.size(); ++k) {
        if (i >= io::field_count(best[k].kind)) continue;
        for (int bits : {1, 2, 4, 8, 12, 16, 24, 32, 40}) {
          io::Case c = best[k];
          double& x = c.v[static_cast<std::size_t>(i)];
          const double y = keep_bits(x, bits);
          if (y == x) break;  // already that short
          x = y;
          variants.push_back(std::move(c)), owner.push_back(k);
        }
      }
      pick = first_failing();
      for (std::size_t k = 0; k < best.size(); ++k)
        if (pick[k]) best[k] = variants[*pick[k]];
    }
  }
  return best;
}

io::Case minimize_case(const Method& m, const io::Case& input, Verdict verdict) {
  // Every variant of a step in one classify_many call: a user kernel behind a pipe starts one
  // process per call, not one per variant.
  return minimize_cases({input}, [&](const std::vector<io::Case>& variants, const std::vector<std::size_t>&) {
    const bool f32 = m.precision == Precision::float32;
    std::vector<io::Case> seen;
    seen.reserve(variants.size());
    for (const auto& c : variants) seen.push_back(f32 ? io::round_to_float(c) : c);
    std::vector<io::CaseResult> got(seen.size());
    m.classify_many(seen, got);
    std::vector<bool> ok;
    for (std::size_t k = 0; k < seen.size(); ++k) {
      Stats ignored;
      Judged j;
      j.input = seen[k];
      j.want = exact_classify(seen[k]);
      j.got = got[k];
      judge_answer(m, j, ignored);
      ok.push_back(j.verdict == verdict && is_mismatch(m, j));
    }
    return ok;
  }).front();
}

FuzzResult run_fuzz(const FuzzOptions& opt) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const std::clock_t cpu_start = std::clock();
  const std::size_t per_round = opt.batch * opt.families.size();
  const std::size_t all_rounds =
      opt.max_cases ? (opt.max_cases + per_round - 1) / std::max<std::size_t>(per_round, 1) : SIZE_MAX;
  // Workers take this shard's rounds in order: local round i is round i * shard_count + shard_index.
  const std::size_t shards = std::max<std::size_t>(opt.shard_count, 1), shard = opt.shard_index;
  const std::size_t round_limit = all_rounds == SIZE_MAX ? SIZE_MAX
                                  : all_rounds > shard   ? (all_rounds - shard + shards - 1) / shards
                                                         : 0;
  const int jobs = std::max(1, opt.jobs);
  // A worker runs at most this many rounds ahead of the oldest one not yet folded in.
  const std::size_t window = 4 * static_cast<std::size_t>(jobs);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mu;
  std::condition_variable folded;
  std::map<std::size_t, RoundOutput> pending;  // finished rounds waiting for an older one
  std::size_t next_fold = 0;                   // the local round to fold next
  std::size_t cases_done = 0;
  std::map<std::string, std::size_t> mismatch_count;
  FuzzResult res;
  std::map<std::pair<std::string, std::string>, std::size_t> kept;

  // Folds a finished round into the result (under `mu`, in round order: the result does not depend
  // on thread timing). Findings beyond keep_per_group are counted, not kept.
  auto fold = [&](RoundOutput& out) {
    ++res.rounds;
    res.cases += out.cases;
    for (auto& [k, s] : out.stats) res.stats[k].add(s);
    for (auto& f : out.findings) {
      const auto key = std::make_pair(f.method, f.family);
      ++res.mismatches[key];
      if (kept[key]++ < opt.keep_per_group) res.findings.push_back(std::move(f));
    }
  };
  auto worker = [&] {
    while (!stop.load()) {
      const std::size_t r = next.fetch_add(1);
      if (r >= round_limit) break;
      {
        std::unique_lock<std::mutex> lock(mu);
        // Every round handed out is run, even after a stop, so the rounds done are 0..R-1; the
        // worker running round next_fold never waits, so this wait ends.
        folded.wait(lock, [&] { return r < next_fold + window; });
      }
      RoundOutput out = run_round(opt, r * shards + shard);
      std::lock_guard<std::mutex> lock(mu);
      cases_done += out.cases;
      for (const auto& f : out.findings) ++mismatch_count[f.method];
      pending.emplace(r, std::move(out));
      for (auto it = pending.begin(); it != pending.end() && it->first == next_fold; it = pending.begin()) {
        fold(it->second);
        pending.erase(it);
        ++next_fold;
      }
      folded.notify_all();
      if (opt.seconds > 0 && std::chrono::duration<double>(clock::now() - start).count() >= opt.seconds) stop = true;
    }
    folded.notify_all();
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
  // Progress from the calling thread while the workers run.
  const auto tick = std::chrono::duration<double>(std::clamp(opt.progress_seconds, 0.01, 60.0));
  const auto sleep_step = std::chrono::duration_cast<clock::duration>(tick / 10);
  while (opt.progress) {
    {
      std::lock_guard<std::mutex> lock(mu);
      if (stop.load() || next.load() >= round_limit) break;
      FuzzProgress p;
      p.seconds = std::chrono::duration<double>(clock::now() - start).count();
      p.cases = cases_done;
      for (const Method* m : opt.methods) p.mismatches.emplace_back(m->name, mismatch_count[m->name]);
      opt.progress(p);
    }
    for (int i = 0; i < 10 && !stop.load() && next.load() < round_limit; ++i) std::this_thread::sleep_for(sleep_step);
  }
  for (auto& t : threads) t.join();
  // Every round handed out was run and folded by the worker that completed 0..r: none is pending.
  for (auto& [r, out] : pending) fold(out);
  pending.clear();

  // Minimize the first minimize_per_group kept findings of each method x family (a kernel failure
  // is not minimized: the kernel is re-run for every try, and may hang each time).
  std::map<std::pair<std::string, std::string>, std::size_t> minimized;
  for (auto& f : res.findings) {
    const auto key = std::make_pair(f.method, f.family);
    const Method* m = nullptr;
    for (const Method* x : opt.methods)
      if (x->name == f.method) m = x;
    if (f.verdict != Verdict::kernel_failure && minimized[key]++ < opt.minimize_per_group) {
      f.input = minimize_case(*m, f.input, f.verdict);
      const Judged j = judge(*m, f.input);
      f.got = j.got, f.want = j.want, f.ulps = j.ulps;
      f.minimized = true;
    }
  }
  for (const Method* m : opt.methods)
    for (const gen::Family* f : opt.families) res.mismatches.try_emplace({m->name, f->name}, 0);
  std::stable_sort(res.findings.begin(), res.findings.end(), [](const FuzzFinding& a, const FuzzFinding& b) {
    return std::tie(a.method, a.family) < std::tie(b.method, b.family);
  });
  for (const Method* m : opt.methods)
    if (m->take_failures)
      for (auto& kf : m->take_failures()) res.kernel_failures.emplace_back(m->name, std::move(kf));
  res.seconds = std::chrono::duration<double>(clock::now() - start).count();
  res.cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return res;
}

}  // namespace rayproof::verify
