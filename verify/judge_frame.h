#pragma once
/// What the judges of whole functions (casters, containment, distance: docs/check.md)
/// share, below their own sets, exact answers and counts:
/// - run_in_batches: a function of the caller's process called batch by batch, an exception
///   failing that batch and kept as a note;
/// - run_line_batches: a program speaking a line protocol (LineChild) fed the mesh once, then
///   batches of items of one set each, read one answer line per item; a crash, an early exit, a
///   hang or an unreadable line fails the batch's rest and is kept as an event sentence, and the
///   program is started again (dropped after 20 failures);
/// - mesh_protocol_head, parse_fields: the protocols' header and answer lines;
/// - KindQuota: the first N reproducers of each kind;
/// - exact_number, finite: how reproducers print numbers.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <fmt/core.h>

#include "rayproof/vec3.h"
#include "rayproof/verify/judge_counters.h"

namespace rayproof::verify {

/// Calls `call(at, n)` for every batch [at, at + n) of `count` items; an exception marks the batch
/// failed (`mark(at, n, true)`, else `mark(at, n, false)`) and its message is kept in `error` (the
/// first one only).
template <class Call, class Mark>
void run_in_batches(std::size_t count, std::size_t batch, std::string& error, Call&& call, Mark&& mark) {
  batch = batch > 0 ? batch : 1;
  for (std::size_t at = 0; at < count; at += batch) {
    const std::size_t n = std::min(batch, count - at);
    bool failed = false;
    try {
      call(at, n);
    } catch (const std::exception& e) {
      failed = true;
      if (error.empty()) error = e.what();
    } catch (...) {
      failed = true;
      if (error.empty()) error = "unknown exception";
    }
    mark(at, n, failed);
  }
}

/// How a line protocol names its items: "ray"/"rays", "point"/"points".
struct LineItems {
  std::string_view one, many;
};

struct LineBatchOptions {
  double timeout_seconds = 10;  ///< per answer line (the first one of a batch included)
  std::size_t batch = 1024;     ///< items per batch
};

/// A run of a program: which items failed, the events (one sentence per failure), the starts, and
/// its wall time.
struct LineBatchRun {
  std::vector<bool> failed;
  std::vector<std::string> events;
  std::size_t starts = 0;
  double seconds = 0;  ///< from the first start to the end: starts, the protocol's text and waits included
};

/// A program's run with its answers (each Answer has a `failed` flag), in item order.
template <class Answer>
struct ExecRun {
  std::vector<Answer> answers;
  std::vector<std::string> events;  ///< "crashed (killed by signal 11 (Segmentation fault)) ..." per failure
  std::size_t starts = 0;           ///< times the program was started
  double seconds = 0;               ///< the run's wall time (LineBatchRun::seconds)
};

/// The answers read during `run`, with its failures marked on them.
template <class Answer>
[[nodiscard]] ExecRun<Answer> with_failures(std::vector<Answer> answers, LineBatchRun&& run) {
  for (std::size_t i = 0; i < answers.size(); ++i) answers[i].failed = run.failed[i];
  return {std::move(answers), std::move(run.events), run.starts, run.seconds};
}

/// Runs `command` on `set.size()` items: `head` first (at every start), then per batch the line
/// "MANY n" and write(i, message) for each item; `read(line, i)` takes item i's answer line,
/// false when unreadable. Batches hold items of one set (set[i], names[set[i]]); the `invalid`
/// set goes one item per batch, so a crash on a NaN names that item.
[[nodiscard]] LineBatchRun run_line_batches(const std::string& command, const std::string& head, LineItems items,
                                            std::span<const std::uint8_t> set, std::span<const std::string> names,
                                            const LineBatchOptions& opt,
                                            const std::function<void(std::size_t, std::string&)>& write,
                                            const std::function<bool(const std::string&, std::size_t)>& read);

/// The protocols' first lines: "PROTOCOL 1", the vertices and the triangles (docs/check.md).
[[nodiscard]] std::string mesh_protocol_head(std::string_view protocol, std::span<const Vec3<double>> vertices,
                                             std::span<const std::array<std::uint32_t, 3>> triangles);

/// Reads a line of fields as the protocols define it: per char of `kinds`, 'd' a double (what
/// strtod reads) into doubles, 'i' an integer (strtoll) into integers; blanks after the last, and
/// nothing else. False when unreadable.
[[nodiscard]] bool parse_fields(const std::string& line, std::string_view kinds, double* doubles, long long* integers);

/// Keeps the first `cap` reproducers of each kind.
class KindQuota {
 public:
  explicit KindQuota(std::size_t cap) : cap_(cap) {}
  /// Whether the next reproducer of `kind` is kept (counts it).
  bool keep(std::string_view kind) {
    for (auto& [k, n] : kept_)
      if (k == kind) return n++ < cap_;
    kept_.emplace_back(std::string(kind), 1);
    return cap_ > 0;
  }

 private:
  std::size_t cap_;
  std::vector<std::pair<std::string, std::size_t>> kept_;
};

/// x exactly: the shortest decimal that reads back to the same double, or inf, -inf, nan.
[[nodiscard]] std::string exact_number(double x);
/// "x y z", each coordinate as exact_number.
[[nodiscard]] std::string exact_point(const Vec3<double>& p);
[[nodiscard]] inline bool finite(const Vec3<double>& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

/// The counters as summary text, one `label value` a line (labels padded to `width`), those
/// `shown(counter)` only.
template <class Counts, std::size_t N, class Shown>
[[nodiscard]] std::string counters_text(const JudgeCounter<Counts> (&table)[N], const std::type_identity_t<Counts>& counts,
                                        std::size_t width, Shown&& shown) {
  std::string text;
  for (const JudgeCounter<Counts>& counter : table)
    if (shown(counter)) text += fmt::format("{:<{}} {}\n", text_label(counter), width, count_of(counts, counter));
  return text;
}

/// Set by set (the items of a set consecutive, sets in order): judge(b, e) timed, then
/// baseline(b, e), rayproof's own query on the same items, timed alone; each set's times added to
/// sets[k].judge_seconds and sets[k].contains_seconds (the baseline's). Returns the totals
/// {judge, baseline}.
template <class Sets, class Judge, class Baseline>
std::pair<double, double> time_by_set(std::span<const std::uint8_t> set, Sets& sets, Judge&& judge,
                                      Baseline&& baseline) {
  using Clock = std::chrono::steady_clock;
  const std::size_t n = set.size();
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b;
    while (e < n && set[e] == set[b]) ++e;
    auto& counts = sets[set[b]];
    const auto start = Clock::now();
    judge(b, e);
    const auto judged = Clock::now();
    baseline(b, e);
    const auto done = Clock::now();
    counts.judge_seconds += std::chrono::duration<double>(judged - start).count();
    counts.contains_seconds += std::chrono::duration<double>(done - judged).count();
    b = e;
  }
  std::pair<double, double> total{0, 0};
  for (const auto& counts : sets) total.first += counts.judge_seconds, total.second += counts.contains_seconds;
  return total;
}

/// judge / baseline as "1.23x", or "-" without a baseline time.
[[nodiscard]] std::string ratio_text(double judge_seconds, double baseline_seconds);

/// The cost lines of a summary: per set "set NAME NOUN n  findings f  cost r of BASELINE", then
/// the total; `Sets` has set, points, findings, judge_seconds, contains_seconds (the baseline's).
template <class Sets>
[[nodiscard]] std::string cost_text(const Sets& sets, std::string_view noun, std::string_view baseline, double judge_seconds,
                                    double baseline_seconds) {
  std::string text;
  for (const auto& set : sets)
    text += fmt::format("set {:<8} {} {:>7}  findings {:>7}  cost {} of {}\n", set.set, noun, set.points, set.findings,
                        ratio_text(set.judge_seconds, set.contains_seconds), baseline);
  text += fmt::format("cost: judging {:.4f} s, rayproof's {} on the same {} {:.4f} s: {}\n", judge_seconds, baseline,
                      noun, baseline_seconds, ratio_text(judge_seconds, baseline_seconds));
  return text;
}

/// The summary's last lines: "note: ..." per note, then the reproducers' lines.
template <class Reproducers>
[[nodiscard]] std::string notes_text(const std::vector<std::string>& notes, const Reproducers& reproducers) {
  std::string text;
  for (const auto& note : notes) text += "note: " + note + "\n";
  for (const auto& reproducer : reproducers) text += reproducer.line + "\n";
  return text;
}

}  // namespace rayproof::verify
