#pragma once
/// A containment function that is a program (`rayproof check --contains NAME=COMMAND`): the line
/// protocol of docs/check.md ("Inside/outside"). The command runs under /bin/sh -c in its own
/// process group; it reads the mesh once, then batches of points, and answers one line per point
/// (0 outside, 1 inside, 2 surface). A program that crashes, exits, hangs (no answer line for
/// `timeout_seconds`) or writes an unreadable line fails the points of that batch it has not
/// answered (ContainsAnswer::failed); it is started again for the next batch, and the event is kept.
/// Batches never span two point sets, and the `invalid` set goes one point per batch. After 20
/// failures the program is dropped: the points left are failures, not sent.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/distance_check.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

using ExecContainsOptions = LineBatchOptions;  ///< timeout per answer line, points per batch
using ExecContainsRun = ExecRun<ContainsAnswer>;

/// Runs `command` on every point (answers in point order).
[[nodiscard]] ExecContainsRun run_exec_contains(const std::string& command, const ContainsMesh& mesh,
                                                const ContainsPoints& points, const ExecContainsOptions& opt = {});

/// One answer line: an integer (what strtoll reads, blanks around it); false when unreadable.
[[nodiscard]] bool parse_contains_answer(const std::string& line, long long& side);

/// A distance function that is a program (`rayproof check --distance NAME=COMMAND`): the same
/// protocol under the name rayproof-distance, one number per answer line (what strtod reads: nan
/// for an invalid point).
using ExecDistanceRun = ExecRun<DistanceAnswer>;
[[nodiscard]] ExecDistanceRun run_exec_distance(const std::string& command, const ContainsMesh& mesh,
                                                const ContainsPoints& points, const ExecContainsOptions& opt = {});
/// One distance answer line: a number (what strtod reads, blanks after it); false when unreadable.
[[nodiscard]] bool parse_distance_answer(const std::string& line, double& d);
/// One answer line of any of the protocol's forms: `d`, `d x y z` (the closest point) or
/// `d x y z triangle` (and its triangle's index); false when unreadable.
[[nodiscard]] bool parse_distance_answer(const std::string& line, DistanceAnswer& a);

}  // namespace rayproof::verify
