#pragma once
/// A user's kernel as a shared library (include/rayproof/plugin.h), loaded in process: a Method whose
/// classify calls the plugin's kind function directly, so verify, report and fuzz run and time it as
/// they run a built-in method.
#include <string>
#include <variant>

#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/plugin.h"

namespace rayproof {

/// Loads PATH (dlopen; a path without a slash is taken relative to the working directory, never
/// searched for) and checks its declaration. `name` overrides the plugin's own name when not empty.
/// Gives the method, or a one-line message naming the path and what is wrong (missing file, not a
/// shared library, no entry point, wrong ABI version, bad name, precision or kind). The library is
/// never unloaded. An answer outside the vocabulary gives Contact::error and a KernelFailure with the
/// case (take_failures; at most 10000 are kept between two takes).
[[nodiscard]] std::variant<Method, std::string> load_plugin_method(const std::string& path,
                                                                   const std::string& name = "");

/// A plugin's answer as a CaseResult, or a description of why it is outside the vocabulary
/// (plugin.h, "Answers"). Exposed for tests.
[[nodiscard]] std::variant<io::CaseResult, std::string> plugin_answer_to_result(io::Kind kind,
                                                                                const rayproof_answer& a);

}  // namespace rayproof
