#pragma once
/// Turns one of rayproof's own methods into a plugin (rayproof/plugin.h): the plugin description
/// with one function per kind, each building the case from the plugin's inputs, calling the method
/// and writing its full answer (class, T, T2). float_plugin.cpp, robust_plugin.cpp and
/// certified_plugin.cpp use it; a plugin of your own needs none of this, only rayproof/plugin.h.
#include <algorithm>
#include <array>
#include <utility>

#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/plugin.h"

namespace rayproof::examples {

inline void write_answer(const io::CaseResult& r, rayproof_answer* out) {
  if (r.contact == Contact::error) return;  // left at RAYPROOF_NO_ANSWER: a kernel failure
  out->cls = static_cast<int>(r.contact);
  if (r.t) out->t = *r.t, out->has |= RAYPROOF_HAS_T;
  if (r.t2) out->t2 = *r.t2, out->has |= RAYPROOF_HAS_T2;
}

/// MethodOf() gives the wrapped method (built once, on first use).
/// One case per thread, reused: an io::Case holds a std::string, which is not built per call.
inline io::Case& scratch_case(io::Kind k) {
  thread_local io::Case c;
  c.kind = k;
  return c;
}

template <const Method& (*MethodOf)(), io::Kind K>
void on_double(const double* in, rayproof_answer* out) {
  io::Case& c = scratch_case(K);
  std::copy_n(in, io::field_count(K), c.v.begin());
  write_answer(MethodOf().classify(c), out);
}

template <const Method& (*MethodOf)(), io::Kind K>
void on_float(const float* in, rayproof_answer* out) {
  io::Case& c = scratch_case(K);
  std::copy_n(in, io::field_count(K), c.v.begin());
  write_answer(MethodOf().classify(c), out);
}

template <const Method& (*MethodOf)(), std::size_t... I>
std::array<rayproof_kind_fn, sizeof...(I)> all_kinds(std::index_sequence<I...>) {
  return {rayproof_kind_fn{static_cast<int>(io::kAllKinds[I]), &on_double<MethodOf, io::kAllKinds[I]>,
                           &on_float<MethodOf, io::kAllKinds[I]>}...};
}

/// The description of a plugin answering every kind with MethodOf() in its precision.
template <const Method& (*MethodOf)()>
const rayproof_plugin* describe(const char* name) {
  static const auto kinds = all_kinds<MethodOf>(std::make_index_sequence<io::kAllKinds.size()>{});
  static const rayproof_plugin plugin{RAYPROOF_PLUGIN_ABI_VERSION, name,
                                      MethodOf().precision == Precision::float32 ? RAYPROOF_FLOAT : RAYPROOF_DOUBLE,
                                      static_cast<int>(kinds.size()), kinds.data()};
  return &plugin;
}

}  // namespace rayproof::examples
