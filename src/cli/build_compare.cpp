#include "cli/build_compare.h"

#include <fmt/core.h>

#include "verify/check_text.h"

#include <cfloat>
#include <chrono>
#include <cmath>

namespace rayproof::cli {

using verify::plural;

namespace {

bool same_value(const std::optional<double>& a, const std::optional<double>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  if (std::isnan(*a) && std::isnan(*b)) return true;
  return *a == *b && std::signbit(*a) == std::signbit(*b);
}

bool involves_subnormal(const BuildDifference& d, Precision p) {
  for (int i = 0; i < io::field_count(d.input.kind); ++i)
    if (subnormal(d.input.v[static_cast<std::size_t>(i)], p)) return true;
  for (const io::CaseResult* r : {&d.gpu, &d.c})
    for (const auto& x : {r->t, r->t2, r->b1, r->b2})
      if (x && subnormal(*x, p)) return true;
  return false;
}


}  // namespace

bool same_answer(const io::CaseResult& a, const io::CaseResult& b) {
  return a.contact == b.contact && same_value(a.t, b.t) && same_value(a.t2, b.t2) && same_value(a.b1, b.b1) &&
         same_value(a.b2, b.b2);
}

bool subnormal(double x, Precision p) {
  const double smallest = p == Precision::float32 ? double(FLT_MIN) : DBL_MIN;
  return x != 0 && std::isfinite(x) && std::fabs(x) < smallest;
}

BuildComparison compare_builds(const Method& gpu, const Method& c, const Method* precise,
                               std::span<const io::Case> cases, std::size_t keep) {
  BuildComparison r;
  r.gpu = gpu.name;
  r.c = c.name;
  if (precise) r.precise = precise->name;
  std::vector<io::Case> both;
  for (const auto& x : cases)
    if (gpu.supports(x.kind) && c.supports(x.kind)) both.push_back(x);
  std::vector<io::CaseResult> g(both.size()), k(both.size());
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  gpu.classify_many(both, g);
  const auto t1 = clock::now();
  c.classify_many(both, k);
  const auto t2 = clock::now();
  r.gpu_seconds = std::chrono::duration<double>(t1 - t0).count();
  r.c_seconds = std::chrono::duration<double>(t2 - t1).count();
  std::vector<BuildDifference> diffs;
  std::vector<io::Case> differing;
  for (std::size_t i = 0; i < both.size(); ++i) {
    if (same_answer(g[i], k[i])) continue;
    diffs.push_back({both[i], g[i], k[i], std::nullopt, {}});
    differing.push_back(both[i]);
  }
  std::vector<io::CaseResult> pr(differing.size());
  if (precise && !differing.empty()) precise->classify_many(differing, pr);
  r.cases = both.size();
  r.differ = diffs.size();
  for (std::size_t i = 0; i < diffs.size(); ++i) {
    auto& d = diffs[i];
    if (precise) d.precise = pr[i];
    if (precise && same_answer(pr[i], d.c)) {
      d.why = "contraction";
      ++r.contraction;
    } else if (involves_subnormal(d, gpu.precision)) {
      d.why = "subnormal";
      ++r.subnormal;
    } else {
      d.why = "unexplained";
      ++r.unexplained;
    }
    if (r.examples.size() < keep) r.examples.push_back(d);
  }
  return r;
}

std::vector<std::string> comparison_lines(const BuildComparison& r, const std::string& device_note) {
  std::vector<std::string> out;
  out.push_back(fmt::format("# the GPU build '{}' against the C build '{}' of the same formula, on the same inputs",
                            r.gpu, r.c));
  auto rate = [](std::size_t n, double s) {
    return s > 0 ? fmt::format("{:.2f} M cases/s", double(n) / s / 1e6) : std::string("too fast to time");
  };
  if (r.cases > 0)
    out.push_back(fmt::format("speed on these {} cases, one pass each, side by side: '{}' {} (batches through the "
                              "device, copies and pipes included), '{}' {} (one thread)",
                              r.cases, r.gpu, rate(r.cases, r.gpu_seconds), r.c, rate(r.cases, r.c_seconds)));
  if (r.differ == 0) {
    out.push_back(fmt::format("'{}' and '{}' give the same answer (class, t and barycentrics, bit for bit) on all {}.",
                              r.gpu, r.c, plural(r.cases, "case", "cases")));
    return out;
  }
  out.push_back(fmt::format("'{}' and '{}' answer differently on {} of {} cases ({:.2f}%):", r.gpu, r.c, r.differ,
                            r.cases, 100.0 * double(r.differ) / double(r.cases)));
  if (!r.precise.empty())
    out.push_back(fmt::format("  {} of them agree with the C build once every float operation of the shader is "
                              "precise (SPIR-V NoContraction, as `precise` on every step): the device's compiler "
                              "contracted multiply-adds into FMA (or made another rewrite that precise forbids);",
                              r.contraction));
  out.push_back(fmt::format("  {} of them involve a value in the subnormal range (an input, or an answer of either "
                            "build){}{};",
                            r.subnormal,
                            r.precise.empty() ? "" : " and still differ when precise",
                            device_note.empty() ? "" : "; the device: " + device_note));
  out.push_back(fmt::format("  {} of them: neither cause shows.", r.unexplained));
  out.push_back(fmt::format("# the first {}: case line, then both answers{}", r.examples.size(),
                            r.precise.empty() ? "" : " and the precise shader's"));
  for (const auto& d : r.examples)
    out.push_back(fmt::format("{}  # {}: {}; {}: {}{}; {}", io::format_case(d.input), r.gpu, io::format_answer(d.gpu),
                              r.c, io::format_answer(d.c),
                              d.precise ? fmt::format("; precise: {}", io::format_answer(*d.precise)) : "", d.why));
  return out;
}

}  // namespace rayproof::cli
