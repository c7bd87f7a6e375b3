#pragma once
/// An all-hits function that is a program (`rayproof check --crossings NAME=COMMAND`): the line
/// protocol of docs/check.md ("All hits"), run by run_line_batches (judge_frame.h). The program
/// reads the mesh once (`rayproof-crossings 1`), then batches of rays (`rays n`, one ray a line:
/// ox oy oz dx dy dz), and answers one line per ray: the number of hits k, then k pairs
/// `t triangle`. Crashes, hangs, early exits and unreadable lines fail the batch's rest and are
/// kept as events; the program is started again (dropped after 20 failures).
#include <string>
#include <vector>

#include "rayproof/verify/crossings_check.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

using ExecCrossingsOptions = LineBatchOptions;  ///< timeout per answer line, rays per batch
using ExecCrossingsRun = ExecRun<CrossingsAnswer>;

/// Runs `command` on every ray (answers in ray order).
[[nodiscard]] ExecCrossingsRun run_exec_crossings(const std::string& command, const CasterMesh& mesh,
                                                  const CasterRays& rays, const ExecCrossingsOptions& opt = {});

/// One answer line: k (an integer >= 0, at most 1,000,000), then k pairs `t triangle` (what strtod
/// and strtoll read), blanks between and after, nothing else; false when unreadable.
[[nodiscard]] bool parse_crossings_answer(const std::string& line, std::vector<CrossingHit>& hits);

}  // namespace rayproof::verify
