#pragma once
/// The part of `--opencl` that needs no OpenCL (docs/opencl.md): which kinds a user's file defines,
/// the wrapper program around it, and the answer codes read back. Used by rayproof itself and by
/// the device process.
#include <string>
#include <variant>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::opencl {

/// The numbers of fields the wrapper reads per case of kind k (docs/cases.md order).
[[nodiscard]] int fields(io::Kind k);

/// The user function's name for kind k: rayproof_triangle, rayproof_box, ...
[[nodiscard]] std::string function_name(io::Kind k);

/// The kinds whose functions `source` defines (a `rayproof_KIND (` outside comments).
[[nodiscard]] std::vector<io::Kind> kinds_defined(const std::string& source);

struct WrapperOptions {
  Precision precision = Precision::float32;
  bool contract_off = false;  ///< `#pragma OPENCL FP_CONTRACT OFF` before the user's text
};

/// The whole program: a prologue (rayproof_real, the answer codes), `#line 1 "FILE"`, the user's
/// text, then one __kernel rayproof_run_KIND per kind. Build errors in the user's text name FILE
/// and its own line numbers.
[[nodiscard]] std::string wrapper_source(const std::string& user_text, const std::string& file_name,
                                         const std::vector<io::Kind>& kinds, const WrapperOptions& opt);

/// One answer as the wrapper reads it back: the function's return code and what it wrote.
struct RawAnswer {
  int code = -1;
  double t = 0, b1 = 0, b2 = 0;
};

/// The answer codes of docs/opencl.md.
inline constexpr int kMiss = 0, kHit = 1, kHitT = 2, kHitTB = 3;

/// A raw answer as a CaseResult, or why it is outside the vocabulary (docs/opencl.md).
[[nodiscard]] std::variant<io::CaseResult, std::string> to_result(io::Kind kind, const RawAnswer& a);

}  // namespace rayproof::opencl
