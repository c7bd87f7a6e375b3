#pragma once
/// What `rayproof check` prints: about a CheckResult, verify/check_text.h (shared with the Python
/// module); about a mesh check, cli/mesh_check_text.h. Kept apart from the
/// command so that a test can build them from known tallies.
#include <string>
#include <vector>

#include "verify/check_text.h"

namespace rayproof::cli {

using verify::check_sentences;
using verify::check_table;
using verify::reproducer_lines;

}  // namespace rayproof::cli
