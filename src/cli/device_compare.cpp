#include "cli/device_compare.h"

#include "cli/build_compare.h"

#include <fmt/core.h>

#include "verify/check_text.h"

#include <cmath>
#include <cstring>

namespace rayproof::cli {

using verify::plural;

namespace {


bool has_subnormal_float_input(const io::Case& c) {
  for (int i = 0; i < io::field_count(c.kind); ++i)
    if (std::fpclassify(static_cast<float>(c.v[static_cast<std::size_t>(i)])) == FP_SUBNORMAL) return true;
  return false;
}


}  // namespace

DeviceComparison compare_device_builds(const Method& device, const Method& c_build, const Method* uncontracted,
                               bool device_flushes, std::span<const io::Case> cases) {
  DeviceComparison r;
  r.device_name = device.name;
  r.c_name = c_build.name;
  r.device_flushes = device_flushes;
  std::vector<io::CaseResult> dev(cases.size()), c(cases.size()), unc;
  device.classify_many(cases, dev);
  c_build.classify_many(cases, c);
  if (uncontracted) {
    unc.resize(cases.size());
    uncontracted->classify_many(cases, unc);
    r.agree_uncontracted = 0;
    r.uncontracted_differ = 0;
  }
  for (auto* m : {&device, &c_build, uncontracted})
    if (m && m->take_failures) (void)m->take_failures();  // the check reported them
  for (std::size_t i = 0; i < cases.size(); ++i) {
    if (dev[i].contact == Contact::error || c[i].contact == Contact::error) continue;
    ++r.cases;
    const bool unc_same = uncontracted && unc[i].contact != Contact::error && same_answer(unc[i], c[i]);
    if (uncontracted && !unc_same) ++*r.uncontracted_differ;
    if (same_answer(dev[i], c[i])) continue;
    ++r.differ;
    if ((dev[i].contact == Contact::miss) != (c[i].contact == Contact::miss)) ++r.differ_hit;
    if (unc_same) ++*r.agree_uncontracted;
    if (has_subnormal_float_input(cases[i])) ++r.differ_subnormal;
    if (r.examples.size() < 3)
      r.examples.push_back(fmt::format("{}  # {}: {}; {}: {}{}", io::format_case(cases[i]), device.name,
                                       io::format_answer(dev[i]), c_build.name, io::format_answer(c[i]),
                                       uncontracted ? fmt::format("; without contraction: {}", io::format_answer(unc[i]))
                                                    : std::string()));
  }
  return r;
}

std::vector<std::string> device_comparison_sentences(const DeviceComparison& c) {
  std::vector<std::string> s;
  if (c.cases == 0) {
    s.push_back(fmt::format("No case was answered by both {} and {}: nothing to compare.", c.device_name, c.c_name));
    return s;
  }
  if (c.differ == 0) {
    s.push_back(fmt::format("The device build {} answers every one of {} exactly as the C build {} does.",
                            c.device_name, plural(c.cases, "case", "cases"), c.c_name));
  } else {
    s.push_back(fmt::format("The device build {} answers {} of {} cases ({:.2f}%) differently from the C build {} "
                            "(class, t or barycentrics not identical); {} hit against miss.",
                            c.device_name, c.differ, c.cases, 100.0 * double(c.differ) / double(c.cases), c.c_name,
                            plural(c.differ_hit, "of them is", "of them are")));
  }
  if (c.agree_uncontracted && c.differ > 0) {
    const std::size_t a = *c.agree_uncontracted;
    if (a == c.differ && *c.uncontracted_differ == 0)
      s.push_back("Built with `#pragma OPENCL FP_CONTRACT OFF` the device agrees with the C build on every case: the "
                  "differences are the device compiler's contraction of multiply-adds into FMA.");
    else if (a > 0)
      s.push_back(fmt::format("Built with `#pragma OPENCL FP_CONTRACT OFF` the device agrees with the C build on {} of "
                              "the {} differing cases: those are FMA contraction; the build without contraction still "
                              "differs on {}.", a, c.differ, plural(*c.uncontracted_differ, "case", "cases")));
    else
      s.push_back(fmt::format("Built with `#pragma OPENCL FP_CONTRACT OFF` the device still differs on {}: not FMA "
                              "contraction (the device's built-ins, such as dot or division, round otherwise).",
                              plural(*c.uncontracted_differ, "case", "cases")));
  }
  if (c.device_flushes)
    s.push_back(fmt::format("The device flushes subnormal floats to zero (no CL_FP_DENORM in CL_DEVICE_SINGLE_FP_CONFIG); "
                            "{} of the differing cases have a subnormal float input.", c.differ_subnormal));
  else if (c.differ_subnormal > 0)
    s.push_back(fmt::format("{} of the differing cases have a subnormal float input; the device declares subnormal "
                            "support (CL_FP_DENORM), unless --cl-options asks for -cl-denorms-are-zero.",
                            c.differ_subnormal));
  return s;
}

}  // namespace rayproof::cli
