#pragma once
/// What `check --caster`, `--contains`, `--distance` and `--crossings` share (check_caster.cpp,
/// check_contains.cpp, check_distance.cpp, check_crossings.cpp): NAME=COMMAND specs, the options
/// that belong to kernels, a run's JSON fields, its text (header line, summary, events, verdict),
/// the --out report's directory and writing.
/// Header-only: the CLI's files compile in unity batches (src/cli/CMakeLists.txt).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "cli/mesh_modes.h"
#include "rayproof/verify/judge_counters.h"
#include "verify/judge_report.h"

namespace rayproof::cli {

/// A judged function that is a program: `--caster NAME=COMMAND`.
struct NamedCommand {
  std::string name, command;
};

/// The NAME=COMMAND specs of `flag`; nothing (the error printed) when one is not.
inline std::optional<std::vector<NamedCommand>> named_commands(const std::vector<std::string>& specs,
                                                               std::string_view flag) {
  std::vector<NamedCommand> out;
  for (const auto& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      fmt::print(stderr, "rayproof check: {} '{}' is not NAME=COMMAND\n", flag, spec);
      return std::nullopt;
    }
    out.push_back({spec.substr(0, eq), spec.substr(eq + 1)});
  }
  return out;
}

/// Whether an option that applies to kernels was given: --exec, --plugin, --glsl, --opencl,
/// --method, --families, --expect, --max-ulps.
inline bool kernel_options_given(const CheckCliOptions& o) {
  return !o.user.exec.empty() || !o.user.plugin.empty() || !o.user.opencl.empty() || !o.user.glsl.empty() ||
         !o.method.empty() || !o.families.empty() || !o.expect.empty() || o.max_ulps.has_value();
}

/// False (the error printed) unless `seconds` is a positive number.
inline bool positive_seconds(double seconds, std::string_view flag) {
  if (seconds > 0 && std::isfinite(seconds)) return true;
  fmt::print(stderr, "rayproof check: {} must be a positive number of seconds\n", flag);
  return false;
}

/// The exponent K of `--contains-scale 2^K` (written 2^K, or as a number that is a power of two:
/// 0.25, 0x1p600); nothing (the error printed) for anything else.
inline std::optional<int> scale_exponent(const std::string& s, std::string_view flag) {
  if (s.size() > 2 && s[0] == '2' && s[1] == '^') {
    const char* b = s.data() + 2;
    const char* e = s.data() + s.size();
    if (*b == '+') ++b;
    int k = 0;
    const auto [end, ec] = std::from_chars(b, e, k);
    if (ec == std::errc() && end == e && b != e) return k;
  } else if (!s.empty()) {
    char* end = nullptr;
    const double x = std::strtod(s.c_str(), &end);
    int e = 0;
    if (end == s.c_str() + s.size() && x > 0 && std::isfinite(x) && std::frexp(x, &e) == 0.5) return e - 1;
  }
  fmt::print(stderr, "rayproof check: {} '{}' is not a power of two (2^K, e.g. 2^600 or 2^-600, or a number such as 0.25)\n",
             flag, s);
  return std::nullopt;
}

/// Every mesh's vertices times 2^k, exactly, and its name marked `NAME*2^k`; false (the error
/// printed) when a nonzero coordinate would leave the normal range (overflow to infinity, or
/// subnormal: the scaling would not be exact) of double, or with `float32` of float (the float
/// judges round the mesh or the points to float).
inline bool scale_meshes(std::vector<JudgedMesh>& meshes, int k, bool float32, std::string_view flag) {
  if (k == 0) return true;
  const double top = float32 ? double(FLT_MAX) : DBL_MAX, least = float32 ? double(FLT_MIN) : DBL_MIN;
  for (const JudgedMesh& m : meshes)
    for (std::size_t i = 0; i < m.mesh.vertices.size(); ++i)
      for (double c : {m.mesh.vertices[i].x, m.mesh.vertices[i].y, m.mesh.vertices[i].z}) {
        if (c == 0 || !std::isfinite(c)) continue;
        const double s = std::ldexp(c, k);
        if (!(std::fabs(s) <= top) || (float32 && !std::isfinite(float(s))) || std::fabs(s) < least) {
          fmt::print(stderr,
                     "rayproof check: {} 2^{}: {}'s vertex {} has coordinate {} whose scaling {} {}'s range of normal "
                     "numbers (the scaled mesh would not be exact); give a smaller scale\n",
                     flag, k, m.name, i, c, std::fabs(s) < least ? "falls below" : "overflows", float32 ? "float" : "double");
          return false;
        }
      }
  for (JudgedMesh& m : meshes) {
    for (Vec3<double>& v : m.mesh.vertices) v = {std::ldexp(v.x, k), std::ldexp(v.y, k), std::ldexp(v.z, k)};
    m.name += fmt::format("*2^{}", k);
  }
  return true;
}

/// judge / baseline in JSON: null without a baseline time.
inline nlohmann::json ratio_json(double judge_seconds, double baseline_seconds) {
  return baseline_seconds > 0 ? nlohmann::json(judge_seconds / baseline_seconds) : nlohmann::json(nullptr);
}

/// Per set, as JSON: points, findings and the cost ratio (sets with judge_seconds and the
/// baseline's contains_seconds).
template <class Sets>
nlohmann::json set_costs_json(const Sets& sets) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& s : sets)
    out[s.set] = {{"points", s.points}, {"findings", s.findings}, {"cost_ratio", ratio_json(s.judge_seconds, s.contains_seconds)}};
  return out;
}

/// One function's run on one mesh as `--json` prints it: `role` (its name), command, mesh,
/// triangles, events, starts, reproducers, notes, and every counter `shown` by its key. The caller
/// adds what is its judge's own (sets, rule, costs).
template <class Tally, class Counts, std::size_t N, class Shown>
nlohmann::json judged_run_json(std::string_view role, const NamedCommand& fn, const JudgedMesh& mesh, const Tally& tally,
                               const std::vector<std::string>& events, std::size_t starts,
                               const verify::JudgeCounter<Counts> (&table)[N], Shown&& shown) {
  nlohmann::json reproducers = nlohmann::json::array();
  for (const auto& r : tally.reproducers) reproducers.push_back(r.line);
  nlohmann::json out = {{std::string(role), fn.name}, {"command", fn.command}, {"mesh", mesh.name},
                        {"triangles", mesh.mesh.triangles.size()}, {"events", events}, {"starts", starts},
                        {"reproducers", reproducers}, {"notes", tally.notes}};
  for (const verify::JudgeCounter<Counts>& counter : table)
    if (shown(counter)) out[std::string(counter.key)] = verify::count_of(tally, counter);
  return out;
}

/// For each mesh: prepare(mesh) gives what its judgement needs (sets, the exact reference; an
/// exception is printed and ends the run: false), then judge(fn, mesh, prepared) for each function.
template <class Prepare, class Judge>
bool for_each_mesh_and_function(const std::vector<JudgedMesh>& meshes, const std::vector<NamedCommand>& functions,
                                Prepare&& prepare, Judge&& judge) {
  for (const JudgedMesh& m : meshes) {
    std::optional<std::invoke_result_t<Prepare&, const JudgedMesh&>> prepared;
    try {
      prepared.emplace(prepare(m));
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}: {}\n", m.name, e.what());
      return false;
    }
    for (const NamedCommand& fn : functions) judge(fn, m, *prepared);
  }
  return true;
}

/// One run as text: what was judged, the summary, the events, and the verdict (`agreed`, the end
/// of the sentence when nothing was found).
struct JudgedRunText {
  std::string_view role, noun;  ///< "caster", "rays"; "function", "points"
  const NamedCommand& fn;
  const JudgedMesh& mesh;
  std::uint64_t items = 0, findings = 0;
  std::size_t starts = 0;
  std::string summary;
  const std::vector<std::string>& events;
  std::string agreed;  ///< " as exact arithmetic does"
};

inline void print_judged_run(const JudgedRunText& r) {
  fmt::print("\n{} '{}' ({}) on {} ({} triangles): {} {}, started {} time{}\n", r.role, r.fn.name, r.fn.command,
             r.mesh.name, r.mesh.mesh.triangles.size(), r.items, r.noun, r.starts, r.starts == 1 ? "" : "s");
  fmt::print("{}", r.summary);
  for (const auto& e : r.events) fmt::print("event: {}\n", e);
  fmt::print("{}\n", verify::judged_verdict(r.role, r.fn.name, r.findings, r.items, r.noun, r.mesh.name, r.agreed));
}

/// --out DIR of a judge: DIR created before the run (false, the error printed, when it cannot be).
inline bool report_dir_ready(const std::string& dir) {
  if (dir.empty()) return true;
  try {
    verify::make_report_dir(dir);
    return true;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof check: {}\n", e.what());
    return false;
  }
}

/// Writes the report of a judge's --out (the message printed); false when it could not be written.
inline bool write_report(const std::string& dir, const verify::JudgeReport& report) {
  try {
    verify::write_judge_report(dir, report);
    fmt::print(stderr, "rayproof check: wrote {}/report.md and {}/report.html\n", dir, dir);
    return true;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof check: {}\n", e.what());
    return false;
  }
}

}  // namespace rayproof::cli
