#pragma once
/// A caster that is a program (`rayproof check --caster NAME=COMMAND`): the line protocol of
/// docs/check.md ("Whole casters"). The command runs under /bin/sh -c in its own process group; it
/// reads the mesh once, then batches of rays, and answers one line per ray. A caster that crashes,
/// exits, hangs (no answer line for `timeout_seconds`) or writes an unreadable line fails the rays
/// of that batch it has not answered (CasterAnswer::failed); it is started again for the next batch,
/// and the event is kept in `events`. Batches never span two ray sets, and the `invalid` set goes
/// one ray per batch, so a crash on a NaN ray names that ray. After 20 failures the caster is
/// dropped: the rays left are failures, not sent.
#include <cstddef>
#include <string>
#include <vector>

#include "rayproof/verify/caster_check.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

using ExecCasterOptions = LineBatchOptions;  ///< timeout per answer line, rays per batch
using ExecCasterRun = ExecRun<CasterAnswer>;

/// Runs `command` on every ray (answers in ray order).
[[nodiscard]] ExecCasterRun run_exec_caster(const std::string& command, const CasterMesh& mesh, const CasterRays& rays,
                                            const ExecCasterOptions& opt = {});

/// One answer line "T TRIANGLE" read as the protocol defines it; false when unreadable.
[[nodiscard]] bool parse_caster_answer(const std::string& line, double& t, long long& triangle);

}  // namespace rayproof::verify
