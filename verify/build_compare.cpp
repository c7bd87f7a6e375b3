#include "verify/build_compare.h"

#include <fmt/core.h>

#include <cfloat>
#include <chrono>
#include <cmath>

#include "verify/check_text.h"

namespace rayproof::verify {

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
  for (const io::CaseResult* r : {&d.device, &d.c})
    for (const auto& x : {r->t, r->t2, r->b1, r->b2})
      if (x && subnormal(*x, p)) return true;
  return false;
}

const char* without_contraction(DeviceLanguage l) {
  return l == DeviceLanguage::glsl ? "with every float operation of the shader precise (SPIR-V NoContraction, as "
                                     "`precise` on every step)"
                                   : "built with `#pragma OPENCL FP_CONTRACT OFF`";
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

BuildComparison compare_builds(DeviceLanguage language, const Method& device, const Method& c,
                               const Method* uncontracted, std::span<const io::Case> cases, std::size_t keep) {
  BuildComparison r;
  r.language = language;
  r.device = device.name;
  r.c = c.name;
  if (uncontracted) r.uncontracted = uncontracted->name;
  std::vector<io::Case> both;
  for (const auto& x : cases)
    if (device.supports(x.kind) && c.supports(x.kind)) both.push_back(x);
  std::vector<io::CaseResult> dev(both.size()), cb(both.size()), unc;
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  device.classify_many(both, dev);
  const auto t1 = clock::now();
  c.classify_many(both, cb);
  const auto t2 = clock::now();
  r.device_seconds = std::chrono::duration<double>(t1 - t0).count();
  r.c_seconds = std::chrono::duration<double>(t2 - t1).count();
  if (uncontracted) {
    unc.resize(both.size());
    uncontracted->classify_many(both, unc);
  }
  for (const Method* m : {&device, &c, uncontracted})
    if (m && m->take_failures) (void)m->take_failures();
  for (std::size_t i = 0; i < both.size(); ++i) {
    if (dev[i].contact == Contact::error || cb[i].contact == Contact::error) {
      ++r.failed;
      continue;
    }
    ++r.cases;
    const bool unc_ran = uncontracted && unc[i].contact != Contact::error;
    const bool unc_same = unc_ran && same_answer(unc[i], cb[i]);
    if (uncontracted && !unc_same) ++r.uncontracted_differ;
    if (same_answer(dev[i], cb[i])) continue;
    ++r.differ;
    if ((dev[i].contact == Contact::miss) != (cb[i].contact == Contact::miss)) ++r.differ_hit;
    BuildDifference d{both[i], dev[i], cb[i], unc_ran ? std::optional(unc[i]) : std::nullopt, {}};
    if (unc_same) {
      d.why = "contraction";
      ++r.contraction;
    } else if (involves_subnormal(d, device.precision)) {
      d.why = "subnormal";
      ++r.subnormal;
    } else {
      d.why = "unexplained";
      ++r.unexplained;
    }
    if (r.examples.size() < keep) r.examples.push_back(std::move(d));
  }
  return r;
}

std::vector<std::string> comparison_lines(const BuildComparison& r) {
  std::vector<std::string> out;
  out.push_back(fmt::format("# the device build '{}' against the C build '{}' of the same formula, on the same inputs",
                            r.device, r.c));
  auto rate = [](std::size_t n, double s) {
    return s > 0 ? fmt::format("{:.2f} M cases/s", double(n) / s / 1e6) : std::string("too fast to time");
  };
  const std::size_t ran = r.cases + r.failed;
  if (ran > 0)
    out.push_back(fmt::format("speed on these {}, one pass each, side by side: '{}' {} (batches through the "
                              "device, copies and pipes included), '{}' {} (one thread)",
                              plural(ran, "case", "cases"), r.device, rate(ran, r.device_seconds), r.c,
                              rate(ran, r.c_seconds)));
  if (r.failed > 0)
    out.push_back(fmt::format("{} left out: a failure of either build (reported above).",
                              plural(r.failed, "case is", "cases are")));
  if (r.cases == 0) {
    out.push_back(fmt::format("No case was answered by both '{}' and '{}': nothing to compare.", r.device, r.c));
    return out;
  }
  if (r.differ == 0) {
    out.push_back(fmt::format("'{}' and '{}' give the same answer (class, t and barycentrics, bit for bit) on all {}.",
                              r.device, r.c, plural(r.cases, "case", "cases")));
  } else {
    out.push_back(fmt::format("'{}' and '{}' answer differently on {} of {} cases ({:.2f}%), {} hit against miss:",
                              r.device, r.c, r.differ, r.cases, 100.0 * double(r.differ) / double(r.cases),
                              plural(r.differ_hit, "of them", "of them")));
    if (!r.uncontracted.empty())
      out.push_back(fmt::format("  {} of them agree with the C build {}: the device's compiler contracted "
                                "multiply-adds into FMA (or made another rewrite that this forbids);",
                                r.contraction, without_contraction(r.language)));
    out.push_back(fmt::format("  {} of them involve a value in the subnormal range (an input, or an answer of either "
                              "build){}{};",
                              r.subnormal, r.uncontracted.empty() ? "" : " and still differ without contraction",
                              r.device_note.empty() ? "" : "; the device: " + r.device_note));
    out.push_back(fmt::format("  {} of them: neither cause shows.", r.unexplained));
  }
  if (!r.uncontracted.empty())
    out.push_back(r.uncontracted_differ == 0
                      ? fmt::format("The build without contraction ('{}') agrees with the C build on every case.",
                                    r.uncontracted)
                      : fmt::format("The build without contraction ('{}') differs from the C build on {}.",
                                    r.uncontracted, plural(r.uncontracted_differ, "case", "cases")));
  if (!r.examples.empty()) {
    out.push_back(fmt::format("# the first {}: case line, then both answers{}, and the cause", r.examples.size(),
                              r.uncontracted.empty() ? "" : " and the build without contraction's"));
    for (const auto& d : r.examples)
      out.push_back(fmt::format("{}  # {}: {}; {}: {}{}; {}", io::format_case(d.input), r.device,
                                io::format_answer(d.device), r.c, io::format_answer(d.c),
                                d.uncontracted ? fmt::format("; without contraction: {}", io::format_answer(*d.uncontracted))
                                               : "",
                                d.why));
  }
  return out;
}

}  // namespace rayproof::verify
