#include "cli/fuzz_summary.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

namespace rayproof::cli {

namespace {

nlohmann::json stats_json(const verify::FuzzTally& t) {
  const verify::Stats& s = t.counts;
  nlohmann::json h = nlohmann::json::array();
  for (const auto& b : t.ulps.buckets()) h.push_back({b.lo, b.hi, b.count});
  return {{"cases", s.cases},
          {"false_hit", s.false_hit},
          {"false_miss", s.false_miss},
          {"wrong_hit_class", s.wrong_hit_class},
          {"wrong_class", s.wrong_class},
          {"fallbacks", s.fallbacks},
          {"kernel_failures", s.kernel_failures},
          {"coarse", s.coarse},
          {"ulp_buckets", h},
          {"ulp_min", t.ulps.min()},
          {"ulp_max", t.ulps.max()},
          {"bary_count", t.bary_count},
          // JSON has no infinity: a NaN barycentric (counted as infinitely wrong) is written as null.
          {"bary_error_max", std::isfinite(t.bary_max) ? nlohmann::json(t.bary_max) : nlohmann::json()},
          {"promised", s.promised},
          {"promise_broken", s.promise_broken}};
}

/// A row of a version 2 summary (t errors as histogram buckets), or of version 1 (t errors as exact
/// [value, count] pairs, barycentric errors listed).
verify::FuzzTally stats_from_json(const nlohmann::json& j, int version) {
  verify::FuzzTally t;
  verify::Stats& s = t.counts;
  s.cases = j.at("cases").get<std::size_t>();
  s.false_hit = j.at("false_hit").get<std::size_t>();
  s.false_miss = j.at("false_miss").get<std::size_t>();
  s.wrong_hit_class = j.at("wrong_hit_class").get<std::size_t>();
  s.wrong_class = j.at("wrong_class").get<std::size_t>();
  s.fallbacks = j.at("fallbacks").get<std::uint64_t>();
  s.kernel_failures = j.at("kernel_failures").get<std::size_t>();
  s.coarse = j.at("coarse").get<std::size_t>();
  if (version == 1) {
    for (const auto& e : j.at("ulps")) {
      const auto n = e.at(1).get<std::size_t>();
      if (n > s.cases) throw std::runtime_error("a t error count exceeds the cases");
      t.ulps.add(e.at(0).get<std::uint64_t>(), n);
    }
    for (const double e : j.at("bary_errors").get<std::vector<double>>()) ++t.bary_count, t.bary_max = std::max(t.bary_max, e);
  } else {
    std::vector<verify::UlpHistogram::Bucket> bs;
    for (const auto& e : j.at("ulp_buckets"))
      bs.push_back({e.at(0).get<std::uint64_t>(), e.at(1).get<std::uint64_t>(), e.at(2).get<std::uint64_t>()});
    const char* why = "";
    auto h = verify::UlpHistogram::from_buckets(bs, j.at("ulp_min").get<std::uint64_t>(),
                                                j.at("ulp_max").get<std::uint64_t>(), why);
    if (!h) throw std::runtime_error(why);
    t.ulps = std::move(*h);
    t.bary_count = j.at("bary_count").get<std::size_t>();
    const auto& bm = j.at("bary_error_max");
    t.bary_max = bm.is_null() ? INFINITY : bm.get<double>();
    if (t.bary_count > s.cases || !(t.bary_max >= 0)) throw std::runtime_error("bad barycentric error counts");
  }
  if (t.ulps.count() > s.cases) throw std::runtime_error("the t error counts exceed the cases");
  s.promised = j.value("promised", std::size_t{0});
  s.promise_broken = j.value("promise_broken", std::size_t{0});
  if (s.promise_broken > s.promised || s.promised > s.cases) throw std::runtime_error("promise counts exceed the cases");
  return t;
}

std::string shards_text(const std::vector<std::size_t>& v) {
  std::string s;
  for (auto k : v) s += (s.empty() ? "" : ", ") + std::to_string(k + 1);
  return s;
}

}  // namespace

FuzzSummary summarize(const FuzzCampaign& c, std::size_t shard_index, const verify::FuzzResult& r) {
  FuzzSummary s;
  s.campaign = c;
  s.shards = {shard_index};
  s.rounds = r.rounds, s.cases = r.cases, s.seconds = r.seconds, s.cpu_seconds = r.cpu_seconds;
  s.stats = r.stats;
  s.mismatches = r.mismatches;
  return s;
}

std::string to_json(const FuzzSummary& s) {
  // Written row by row, the buckets as text: a JSON tree of the whole summary (up to 7,425 buckets per
  // method x family) took more memory at the end of a 94.7M-case campaign than the campaign itself
  // (peak RSS 39 MB against 21 MB while it ran).
  const auto& c = s.campaign;
  const nlohmann::json head{{"rayproof_fuzz_summary", 2},
                            {"campaign",
                             {{"seed", c.seed},
                              {"methods", c.methods},
                              {"families", c.families},
                              {"batch", c.batch},
                              {"cases", c.max_cases},
                              {"shard_count", c.shard_count}}},
                            {"shards", s.shards},
                            {"rounds", s.rounds},
                            {"cases", s.cases},
                            {"seconds", s.seconds},
                            {"cpu_seconds", s.cpu_seconds}};
  std::string out = head.dump(1);  // "{\n ...\n}"
  out.resize(out.size() - 2);
  out += ",\n \"stats\": [";
  bool first_row = true;
  for (const auto& [key, st] : s.stats) {
    auto j = stats_json(st);
    j.erase("ulp_buckets");
    j["method"] = key.first;
    j["family"] = key.second;
    const auto it = s.mismatches.find(key);
    j["mismatches"] = it == s.mismatches.end() ? 0 : it->second;
    std::string row = j.dump();
    row.pop_back();  // '}'
    row += ", \"ulp_buckets\": [";
    bool first_bucket = true;
    for (const auto& b : st.ulps.buckets()) {
      fmt::format_to(std::back_inserter(row), "{}[{}, {}, {}]", first_bucket ? "" : ", ", b.lo, b.hi, b.count);
      first_bucket = false;
    }
    row += "]}";
    out += (first_row ? "\n  " : ",\n  ") + row;
    first_row = false;
  }
  out += "\n ]\n}\n";
  return out;
}

std::optional<FuzzSummary> summary_from_json(const std::string& text, const std::string& file, std::string& error) {
  try {
    const auto j = nlohmann::json::parse(text);
    if (!j.is_object() || !j.contains("rayproof_fuzz_summary")) {
      error = file + ": not a rayproof fuzz summary (written by `rayproof fuzz --summary`)";
      return std::nullopt;
    }
    const int version = j.at("rayproof_fuzz_summary").is_number_integer() ? j.at("rayproof_fuzz_summary").get<int>() : 0;
    if (version != 1 && version != 2) {
      error = file + ": summary version " + j.at("rayproof_fuzz_summary").dump() + " is not 1 or 2";
      return std::nullopt;
    }
    FuzzSummary s;
    const auto& c = j.at("campaign");
    s.campaign.seed = c.at("seed").get<std::uint64_t>();
    s.campaign.methods = c.at("methods").get<std::vector<std::string>>();
    s.campaign.families = c.at("families").get<std::vector<std::string>>();
    s.campaign.batch = c.at("batch").get<std::size_t>();
    s.campaign.max_cases = c.at("cases").get<std::size_t>();
    s.campaign.shard_count = c.at("shard_count").get<std::size_t>();
    s.shards = j.at("shards").get<std::vector<std::size_t>>();
    for (auto k : s.shards)
      if (k >= s.campaign.shard_count) {
        error = fmt::format("{}: shard {} of a campaign in {} shards", file, k + 1, s.campaign.shard_count);
        return std::nullopt;
      }
    s.rounds = j.at("rounds").get<std::size_t>();
    s.cases = j.at("cases").get<std::size_t>();
    s.seconds = j.at("seconds").get<double>();
    s.cpu_seconds = j.value("cpu_seconds", 0.0);
    for (const auto& row : j.at("stats")) {
      const auto key = std::make_pair(row.at("method").get<std::string>(), row.at("family").get<std::string>());
      s.stats[key] = stats_from_json(row, version);
      s.mismatches[key] = row.at("mismatches").get<std::size_t>();
    }
    return s;
  } catch (const std::exception& e) {
    error = file + ": malformed summary (" + e.what() + ")";
    return std::nullopt;
  }
}

std::optional<FuzzSummary> merge_summaries(const std::vector<FuzzSummary>& parts, const std::vector<std::string>& files,
                                           std::string& error) {
  if (parts.empty()) {
    error = "no summaries to merge";
    return std::nullopt;
  }
  FuzzSummary m;
  m.campaign = parts.front().campaign;
  std::map<std::size_t, std::string> seen;  // shard -> file
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const auto& p = parts[i];
    const auto& a = m.campaign;
    const auto& b = p.campaign;
    std::string diff;
    if (a.seed != b.seed) diff = fmt::format("seed {} and {}", a.seed, b.seed);
    else if (a.methods != b.methods) diff = "methods differ";
    else if (a.families != b.families) diff = "families differ";
    else if (a.batch != b.batch) diff = fmt::format("cases per round {} and {}", a.batch, b.batch);
    else if (a.max_cases != b.max_cases) diff = fmt::format("--cases {} and {}", a.max_cases, b.max_cases);
    else if (a.shard_count != b.shard_count) diff = fmt::format("{} and {} shards", a.shard_count, b.shard_count);
    if (!diff.empty()) {
      error = fmt::format("{} and {} are summaries of different campaigns ({})", files.front(), files[i], diff);
      return std::nullopt;
    }
    for (auto k : p.shards) {
      if (auto it = seen.find(k); it != seen.end()) {
        error = fmt::format("shard {}/{} is in both {} and {}", k + 1, a.shard_count, it->second, files[i]);
        return std::nullopt;
      }
      seen[k] = files[i];
      m.shards.push_back(k);
    }
    m.rounds += p.rounds, m.cases += p.cases, m.seconds = std::max(m.seconds, p.seconds);
    m.cpu_seconds += p.cpu_seconds;
    for (const auto& [k, st] : p.stats) m.stats[k].merge(st);
    for (const auto& [k, n] : p.mismatches) m.mismatches[k] += n;
  }
  std::sort(m.shards.begin(), m.shards.end());
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < m.campaign.shard_count; ++k)
    if (!seen.count(k)) missing.push_back(k);
  if (!missing.empty()) {
    error = fmt::format("the merge lacks {} {} of the campaign's {} (given: {})",
                        missing.size() == 1 ? "shard" : "shards", shards_text(missing), m.campaign.shard_count,
                        shards_text(m.shards));
    return std::nullopt;
  }
  return m;
}

std::string quantile_text(const verify::UlpHistogram::Range& r) {
  if (!r.exact()) return "<=" + std::to_string(r.hi);
  return r.lo == std::numeric_limits<std::uint64_t>::max() ? std::string("NaN t") : std::to_string(r.lo);
}

std::string fuzz_table(const std::vector<std::string>& methods, const std::vector<std::string>& families,
                       const verify::FuzzTallies& stats,
                       const std::map<std::pair<std::string, std::string>, std::size_t>& mismatches) {
  constexpr const char* kRow = "{:<16} {:<24} {:>9} {:>10} {:>9} {:>9} {:>9} {:>12} {:>12}  {}\n";
  std::string s = fmt::format(kRow, "method", "family", "cases", "mismatches", "rate %", "fallbacks", "t p50",
                              "t p99", "t max", "promise");
  bool bucketed = false;
  auto row = [&](const std::string& m, const std::string& f, const verify::FuzzTally& t, std::size_t bad) {
    const auto p50 = t.ulps.quantile(0.5), p99 = t.ulps.quantile(0.99), mx = t.ulps.quantile(1.0);
    bucketed = bucketed || !p50.exact() || !p99.exact();
    const std::size_t n = t.counts.cases;
    s += fmt::format(kRow, m, f, n, bad, fmt::format("{:.4f}", n ? 100.0 * double(bad) / double(n) : 0.0),
                     t.counts.fallbacks, quantile_text(p50), quantile_text(p99), quantile_text(mx),
                     verify::promise_status(t.counts));
  };
  for (const auto& m : methods) {
    std::size_t bad = 0;
    verify::FuzzTally all;
    for (const auto& f : families) {
      auto it = stats.find({m, f});
      if (it == stats.end() || it->second.counts.cases == 0) continue;
      const auto mm = mismatches.find({m, f});
      const std::size_t n = mm == mismatches.end() ? 0 : mm->second;
      row(m, f, it->second, n);
      all.merge(it->second);
      bad += n;
    }
    row(m, "(all)", all, bad);
  }
  s += "t p50, p99, max: the t error in ulps of the class-correct answers (float ulps for float methods); "
       "the max is exact";
  if (bucketed)
    s += fmt::format(";\n  \"<=N\": the percentile lies in a histogram bucket whose upper bound is N (exact counts; "
                     "the value is at most {:.2f}% below N; values below {} are exact)",
                     100.0 * verify::UlpHistogram::kRelativeWidth, verify::UlpHistogram::kExactBelow);
  return s + "\n";
}

std::string speed_text(std::size_t cases, double seconds, double cpu_seconds, int jobs) {
  const double rate = seconds > 0 ? double(cases) / seconds : 0.0;
  std::string s = fmt::format("{} cases in {:.1f} s: {:.0f} cases/s on {} {}, {:.0f} per job", cases, seconds, rate, jobs,
                              jobs == 1 ? "job" : "jobs", rate / std::max(jobs, 1));
  if (cpu_seconds > 0) s += fmt::format("; {:.0f} per CPU second ({:.1f} CPU s)", double(cases) / cpu_seconds, cpu_seconds);
  return s;
}

std::optional<std::pair<std::size_t, std::size_t>> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return std::nullopt;
  std::size_t k = 0, n = 0;
  const char* b = text.data();
  const char* e = b + text.size();
  auto r1 = std::from_chars(b, b + slash, k);
  auto r2 = std::from_chars(b + slash + 1, e, n);
  if (r1.ec != std::errc{} || r1.ptr != b + slash || r2.ec != std::errc{} || r2.ptr != e) return std::nullopt;
  if (n < 1 || n > 1000000 || k < 1 || k > n) return std::nullopt;
  return std::make_pair(k - 1, n);
}

}  // namespace rayproof::cli
