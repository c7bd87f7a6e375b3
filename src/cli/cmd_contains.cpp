/// rayproof contains MESH POINTS [--json] [--rule R] [--winding] [--segments]: inside / outside /
/// surface of each point (rayproof/scene/contains.h, docs/contains.md): on a closed mesh by its exact
/// winding number or parity, on any other mesh by the generalized winding number (w > 1/2, decided
/// with certainty; `--winding` prints w with its bound).
/// A point line is `x y z` (# comments and blank lines skipped); with --segments a line is
/// `px py pz qx qy qz` and the answer is whether the segment meets the surface and where first.
/// Errors (exit 2, one message naming the file and line): a missing or unreadable file, a mesh
/// that is not closed with --rule nonzero or parity, a line that is not three (six) numbers, a NaN or infinite coordinate.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "cli/mesh_input.h"
#include "cli/commands.h"
#include "cli/input.h"
#include "cli/point_lines.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"

namespace rayproof::cli {

namespace {

struct ContainsOptions {
  std::string mesh, points, rule = "automatic";
  bool json = false, winding = false, segments = false;
  int threads = 0;
  double tolerance = 1e-6;
};

}  // namespace

/// Reads lines of `want` numbers; on error returns false with "PATH:LINE: what" in `error`.
bool read_numbers(std::istream& in, const std::string& path, int want, std::vector<double>& out, std::string& error) {
  std::string line;
  for (std::size_t no = 1; std::getline(in, line); ++no) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const char* s = line.c_str();
    int got = 0;
    double xs[6];
    for (;;) {
      while (*s == ' ' || *s == '\t' || *s == '\r' || *s == ',') ++s;
      if (!*s) break;
      char* end = nullptr;
      errno = 0;
      const double x = std::strtod(s, &end);
      if (end == s) {
        error = fmt::format("{}:{}: '{}' is not a number (expected {} numbers per line)", path, no, std::string(s).substr(0, 20), want);
        return false;
      }
      if (got == want) {
        error = fmt::format("{}:{}: more than {} numbers", path, no, want);
        return false;
      }
      if (x != x || x - x != 0) {
        error = fmt::format("{}:{}: coordinate {} is NaN or infinite", path, no, got + 1);
        return false;
      }
      xs[got++] = x;
      s = end;
    }
    if (got == 0) continue;
    if (got != want) {
      error = fmt::format("{}:{}: {} numbers, expected {} ({})", path, no, got, want, want == 3 ? "x y z" : "px py pz qx qy qz");
      return false;
    }
    out.insert(out.end(), xs, xs + want);
  }
  return true;
}

namespace {

ContainsRule parse_rule(const std::string& r) {
  if (r == "nonzero") return ContainsRule::nonzero;
  if (r == "parity") return ContainsRule::parity;
  return r == "winding" ? ContainsRule::winding : ContainsRule::automatic;
}
/// The rule as the summary line states it.
std::string rule_text(const ExactMesh& m) {
  switch (m.rule()) {
    case ContainsRule::parity: return "rule parity";
    case ContainsRule::winding:
      return std::string("rule winding: inside where the generalized winding number > 1/2") +
             (m.closed() ? "" : ", the mesh is not closed");
    default: return "rule nonzero";
  }
}

int run_contains(const ContainsOptions& opt) {
  const char* me = "rayproof contains";
  auto loaded = read_closed_mesh(me, opt.mesh, parse_rule(opt.rule));
  if (!loaded) return 2;
  const std::unique_ptr<ExactMesh>& cm = loaded->closed;
  // --winding: the exact integer on a closed oriented mesh (unless the winding rule was asked for),
  // else the generalized winding number with its bound.
  const bool integer_winding = cm->closed() && cm->oriented() && cm->rule() != ContainsRule::winding;
  if (opt.winding && !(opt.tolerance > 0)) {
    fmt::print(stderr, "{}: --tolerance must be positive\n", me);
    return 2;
  }
  Input in = open_input(opt.points);
  if (!in.stream) {
    fmt::print(stderr, "{}: {}\n", me, in.error);
    return 2;
  }
  std::vector<double> xs;
  std::string error;
  const int per = opt.segments ? 6 : 3;
  if (!read_numbers(*in.stream, opt.points, per, xs, error)) {
    fmt::print(stderr, "{}: {}\n", me, error);
    return 2;
  }
  const std::size_t n = xs.size() / per;
  std::string out;
  std::size_t tally[4] = {0, 0, 0, 0};
  std::string windings;  // JSON with --winding: the winding numbers (null on the surface)  // outside, inside, surface; segments: crossing / not
  if (opt.json) out += fmt::format("{{\"mesh\": \"{}\", \"triangles\": {}, \"oriented\": {}, \"rule\": \"{}\", \"{}\": [", opt.mesh,
                                   cm->triangle_count(), cm->oriented() ? "true" : "false", to_string(cm->rule()),
                                   opt.segments ? "segments" : "points");
  if (opt.segments) {
    for (std::size_t i = 0; i < n; ++i) {
      const double* s = &xs[6 * i];
      const SegmentHit h = cm->segment({s[0], s[1], s[2]}, {s[3], s[4], s[5]});
      ++tally[h.crosses ? 0 : 1];
      if (opt.json) {
        out += fmt::format("{}{{\"crosses\": {}, \"contact\": \"{}\", \"t\": {}, \"triangle\": {}, \"p\": \"{}\", \"q\": \"{}\"}}",
                           i ? ", " : "", h.crosses ? "true" : "false", h.crosses ? to_string(h.contact) : "miss",
                           h.crosses ? io::format_double(h.t) : "null", h.crosses ? std::to_string(h.triangle) : "null",
                           to_string(h.p_side), to_string(h.q_side));
      } else if (h.crosses) {
        out += fmt::format("{} {} {} {} {}\n", to_string(h.contact), io::format_double(h.t), h.triangle, to_string(h.p_side),
                           to_string(h.q_side));
      } else {
        out += fmt::format("miss - - {} {}\n", to_string(h.p_side), to_string(h.q_side));
      }
    }
  } else {
    std::vector<Side> sides(n);
    cm->contains(std::span<const Vec3<double>>(reinterpret_cast<const Vec3<double>*>(xs.data()), n), sides, opt.threads);
    for (std::size_t i = 0; i < n; ++i) {
      ++tally[int(sides[i])];
      std::string w, wj;  // text and JSON
      if (opt.winding && sides[i] != Side::surface) {
        const Vec3<double> p{xs[3 * i], xs[3 * i + 1], xs[3 * i + 2]};
        if (integer_winding) {
          w = wj = std::to_string(cm->winding(p));
        } else {
          const WindingValue v = cm->winding_value(p, opt.tolerance);
          w = fmt::format("{} +- {:.3g}", io::format_double(v.w), v.bound);
          wj = fmt::format("{{\"w\": {}, \"bound\": {:.3g}}}", io::format_double(v.w), v.bound);
        }
      }
      if (opt.json) {
        out += fmt::format("{}\"{}\"", i ? ", " : "", to_string(sides[i]));
        if (opt.winding) windings += (i ? ", " : "") + (wj.empty() ? std::string("null") : wj);
      } else
        out += std::string(to_string(sides[i])) + (w.empty() ? "" : " " + w) + "\n";
      if (out.size() > (1 << 16) && !opt.json) std::fwrite(out.data(), 1, out.size(), stdout), out.clear();
    }
  }
  if (opt.json) {
    if (opt.segments)
      out += fmt::format("], \"count\": {}, \"crossing\": {}, \"not_crossing\": {}}}\n", n, tally[0], tally[1]);
    else
      out += (opt.winding ? "], \"winding\": [" + windings : std::string()) +
             fmt::format("], \"count\": {}, \"inside\": {}, \"outside\": {}, \"surface\": {}}}\n", n, tally[1], tally[0], tally[2]);
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (opt.segments)
    fmt::print(stderr, "{}: {} segments: {} meet the surface, {} do not\n", me, n, tally[0], tally[1]);
  else
    fmt::print(stderr, "{}: {} points: {} inside, {} outside, {} on the surface ({}, {} triangles)\n", me, n, tally[1],
               tally[0], tally[2], rule_text(*cm), cm->triangle_count());
  return 0;
}

}  // namespace

Run add_contains(CLI::App& app) {
  auto opt = std::make_shared<ContainsOptions>();
  auto* sub = app.add_subcommand("contains", "Inside / outside / surface of points (or segments), decided with certainty: "
                                              "closed meshes by the winding number, others by the generalized winding number");
  sub->add_option("mesh", opt->mesh, "Mesh file (.off .obj .ply .stl); open meshes and soups too")->required();
  sub->add_option("points", opt->points, "Point file (x y z per line), or - for standard input")->required();
  sub->add_flag("--json", opt->json, "Print one JSON object (the sides and their tallies)");
  sub->add_option("--rule", opt->rule,
                  "automatic (closed: nonzero winding when oriented, else parity; not closed: winding), nonzero, parity, "
                  "or winding (generalized winding number > 1/2, any mesh)")
      ->check(CLI::IsMember({"automatic", "nonzero", "parity", "winding"}))
      ->capture_default_str();
  sub->add_flag("--winding", opt->winding,
                "Append the winding number to each line: the exact integer on a closed oriented mesh, else the "
                "generalized winding number and its bound ('W +- BOUND')");
  sub->add_option("--tolerance", opt->tolerance, "--winding: refine w until its bound is at most this")->capture_default_str();
  sub->add_flag("--segments", opt->segments, "Lines are segments 'px py pz qx qy qz': CONTACT T TRIANGLE P_SIDE Q_SIDE, or miss");
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)")->capture_default_str();
  return [opt] { return run_contains(*opt); };
}

}  // namespace rayproof::cli
