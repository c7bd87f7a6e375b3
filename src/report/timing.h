#pragma once
/// Run time per case of a method on a batch of cases: the median of repeated timed batches.
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::report {

/// Nanoseconds per case (median over `reps` batches; slow methods get fewer repetitions). The
/// inputs must already be what the method sees (float-rounded for float methods). A method with
/// classify_batch (a user's kernel behind a pipe) is timed through classify_many over the whole batch.
[[nodiscard]] double ns_per_case(const Method& m, const std::vector<io::Case>& inputs, int reps = 7);

}  // namespace rayproof::report
