#pragma once
/// A user's GLSL intersection functions (docs/shaders.md) wrapped into one compute shader per kind,
/// and the SPIR-V pass that makes every float operation `precise` (NoContraction). Text and words
/// only: no Vulkan, no compiler.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::glsl {

/// Cases per workgroup of the wrapper (local_size_x).
inline constexpr unsigned kWorkgroup = 64;
/// Reals per case in the input buffer (15 used at most, padded to 16) and per answer (code, t, b1, b2).
inline constexpr unsigned kInReals = 16, kOutReals = 4;

/// The answer codes a user's function returns (docs/shaders.md).
enum AnswerCode : int { kMiss = 0, kHit = 1, kHitT = 2, kHitTB = 3 };

/// The function a kind's shader calls: "rayproof_triangle", ... (the OpenCL names too).
[[nodiscard]] std::string function_name(io::Kind k);

/// The old GLSL spelling of a kind's function, "rp_triangle", ...: accepted for one release, with
/// legacy_names_warning's message, where the text does not define the new name.
[[nodiscard]] std::string legacy_function_name(io::Kind k);

/// The signature documented for a kind in a precision, as GLSL
/// ("int rayproof_sphere(vec3 o, vec3 d, vec3 center, float radius, out float t)").
[[nodiscard]] std::string signature(io::Kind k, Precision p);

/// The kinds whose function the text defines (a name rayproof_KIND, or the old rp_KIND, followed
/// by `(` outside comments), in io::Kind order.
[[nodiscard]] std::vector<io::Kind> defined_kinds(std::string_view user_text);

/// The kinds the text defines only under the old name rp_KIND.
[[nodiscard]] std::vector<io::Kind> legacy_kinds(std::string_view user_text);

/// The deprecation message for a text that uses the old names (which, what to rename them to, and
/// until when they work); empty when it uses none.
[[nodiscard]] std::string legacy_names_warning(std::string_view file, std::string_view user_text);

/// The user's text as it goes into the wrapper: a `#version` line blanked (the wrapper has its
/// own), every line kept so that line numbers stay the user's.
[[nodiscard]] std::string prepare_user_text(std::string_view user_text);

/// The compute shader for kind k: the wrapper's header, `#line 1 "LABEL"` and the user's text
/// (prepared), then main() under `#line 1 "rayproof wrapper calling rayproof_KIND"` (or the
/// old rp_KIND where the text defines only that). A compile error in
/// the user's text names LABEL and the user's line.
[[nodiscard]] std::string wrap(std::string_view user_text, std::string_view label, io::Kind k, Precision p);

/// Where the compiler points into the wrapper instead of the user's text (a signature that does not
/// match the call): the message with the signature the wrapper expects appended; else unchanged.
[[nodiscard]] std::string explain_compile_error(const std::string& message, io::Kind k, Precision p);

/// SPIR-V words with an `OpDecorate ID NoContraction` for the result of every float arithmetic
/// instruction (add, sub, mul, div, negate, dot, vector/matrix products, and GLSL.std.450 calls):
/// what `precise` on every step does. Empty when the words are not a SPIR-V module.
[[nodiscard]] std::vector<std::uint32_t> decorate_no_contraction(const std::vector<std::uint32_t>& spirv);

}  // namespace rayproof::glsl
