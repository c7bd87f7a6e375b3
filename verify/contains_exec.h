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

namespace rayproof::verify {

struct ExecContainsOptions {
  double timeout_seconds = 10;  ///< per answer line (the first one of a batch included)
  std::size_t batch = 1024;     ///< points per batch
};

struct ExecContainsRun {
  std::vector<ContainsAnswer> answers;
  std::vector<std::string> events;  ///< one sentence per failure
  std::size_t starts = 0;           ///< times the program was started
};

/// A run of a program on points: which points failed, the events, the starts (the answers are the
/// caller's, through run_exec_points' callback).
struct ExecPointsRun {
  std::vector<bool> failed;
  std::vector<std::string> events;
  std::size_t starts = 0;
};

/// Runs `command` on every point under the protocol named `protocol` (its first line: `protocol 1`,
/// then the mesh and batches of points as docs/check.md says); `answer(line, i)` reads point i's
/// answer line, false when unreadable (the batch's rest fails).
[[nodiscard]] ExecPointsRun run_exec_points(const std::string& command, const char* protocol, const ContainsMesh& mesh,
                                            const ContainsPoints& points, const ExecContainsOptions& opt,
                                            const std::function<bool(const std::string&, std::size_t)>& answer);

/// Runs `command` on every point (answers in point order).
[[nodiscard]] ExecContainsRun run_exec_contains(const std::string& command, const ContainsMesh& mesh,
                                                const ContainsPoints& points, const ExecContainsOptions& opt = {});

/// One answer line: an integer (what strtoll reads, blanks around it); false when unreadable.
[[nodiscard]] bool parse_contains_answer(const std::string& line, long long& side);

/// A distance function that is a program (`rayproof check --distance NAME=COMMAND`): the same
/// protocol under the name rayproof-distance, one number per answer line (what strtod reads: nan
/// for an invalid point).
struct ExecDistanceRun {
  std::vector<DistanceAnswer> answers;
  std::vector<std::string> events;
  std::size_t starts = 0;
};
[[nodiscard]] ExecDistanceRun run_exec_distance(const std::string& command, const ContainsMesh& mesh,
                                                const ContainsPoints& points, const ExecContainsOptions& opt = {});
/// One distance answer line: a number (what strtod reads, blanks after it); false when unreadable.
[[nodiscard]] bool parse_distance_answer(const std::string& line, double& d);

}  // namespace rayproof::verify
