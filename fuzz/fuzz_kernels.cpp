// libFuzzer harness: raw bytes become one case of each kind; every registered method answers it.
// Nothing may crash or trip a sanitizer, every answer is a docs/cases.md class, and any method that
// promises exactness (certified) must equal exact.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <cstdio>

#include "registry/registry.h"
#include "io/case_file.h"
#include "verify/exact_method.h"
#include "verify/fuzz_campaign.h"

using namespace rayproof;

namespace {
/// Two encodings: mode 0 reads raw doubles (NaN, subnormals, huge values); mode 1 reads small
/// signed integers scaled by a power of two (exact contacts, degeneracies, ties).
io::Case decode(const std::uint8_t* data, std::size_t size) {
  io::Case c;
  if (size == 0) return c;
  c.kind = io::kAllKinds[data[0] % 6];
  const bool small = (data[0] / 6) % 2 == 1;
  const int scale = size > 1 ? static_cast<int>(static_cast<std::int8_t>(data[1])) : 0;
  data += 2 < size ? 2 : size;
  size -= 2 < size ? 2 : size;
  for (int i = 0; i < io::field_count(c.kind); ++i) {
    double v = 0;
    if (small) {
      if (static_cast<std::size_t>(i) < size) v = std::ldexp(static_cast<double>(static_cast<std::int8_t>(data[i])), scale);
    } else if (static_cast<std::size_t>(i + 1) * 8 <= size) {
      std::memcpy(&v, data + static_cast<std::size_t>(i) * 8, 8);
    }
    c.v[static_cast<std::size_t>(i)] = v;
  }
  return c;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const io::Case c = decode(data, size);
  const auto& methods = registry::all_methods().all();
  for (const auto& m : methods) {
    if (!m.supports(c.kind)) continue;
    const io::CaseResult got = m.run(c);
    if (got.contact == Contact::error) {
      std::fprintf(stderr, "method %s answered `error` on %s\n", m.name.c_str(), io::format_case(c).c_str());
      std::abort();
    }
    // Methods that promise the exact class (certified, exact) are held to their whole promise here;
    // the weaker promises (robust's no-false-miss) are checked by `rayproof fuzz`.
    const Promise promise = m.promise(c.kind);
    if (promise.exact_class) {
      const io::CaseResult want = verify::exact_classify(m.precision == Precision::float32 ? io::round_to_float(c) : c);
      const auto v = verify::judge_class(got, want);
      const auto u = v == verify::Verdict::agree ? verify::t_error_ulps(got, want, m.precision) : 0;
      if (verify::breaks_promise(promise, v, u, want)) {
        std::fprintf(stderr, "%s breaks its promise (%s) on\n%s\ngot %s, exact %s\n", m.name.c_str(),
                     promise.describe().c_str(), io::format_case(c).c_str(), io::format_result(got).c_str(),
                     io::format_result(want).c_str());
        std::abort();
      }
    }
  }
  return 0;
}
