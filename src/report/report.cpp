#include "report/report.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "report/report_text.h"
#include "report/timing.h"
#include "verify/exact_method.h"

namespace rayproof::report {

Report build_report(const std::vector<io::Case>& given, const std::vector<const Method*>& methods,
                    const std::function<void(const std::string&)>& progress) {
  // A family that spans several kinds (invalid input) is reported once per kind: rows are per kind.
  std::map<std::string, std::set<io::Kind>> kinds_of;
  for (const auto& c : given) kinds_of[verify::group_of(c)].insert(c.kind);
  std::vector<io::Case> cases = given;
  for (auto& c : cases)
    if (kinds_of[verify::group_of(c)].size() > 1) c.family = verify::group_of(c) + "_" + std::string(io::to_string(c.kind));
  Report rep;
  rep.title = "rayproof: error against run time";
  progress(fmt::format("exact answers for {} cases (twice where float rounding changes the input)", cases.size()));
  const verify::ExactAnswers exact = verify::exact_answers(cases);
  progress("comparing every method with exact");
  const verify::Comparison cmp = verify::compare(cases, exact, methods, kReproducersPerMethod);
  for (const auto& x : cmp.mismatches) {
    Precision p = Precision::float64;
    for (const Method* m : methods)
      if (m->name == x.method) p = m->precision;
    rep.reproducers.push_back(fmt::format("{}  # {}: {}, got {}, exact {}{}", io::format_case(x.input), x.method,
                                          verify::to_string(x.verdict), io::format_answer(x.got), io::format_result(x.want),
                                          x.verdict == verify::Verdict::agree ? fmt::format(" (t off by {} ulps)", ulp_text(x.ulps, p)) : ""));
  }
  rep.reproducers_intro = fmt::format(
      "The first {} cases of each method on which it disagrees with exact (a class error, or t more than 1 ulp off), "
      "in the order generated: one case-file line each, the input as the method saw it (`rayproof classify --method "
      "NAME` answers it again).",
      kReproducersPerMethod);
  for (const Method* m : methods)
    if (m->take_failures)
      for (auto& f : m->take_failures()) rep.kernel_failures.emplace_back(m->name, std::move(f));

  std::map<std::string, std::vector<io::Case>> by_group;
  for (const auto& c : cases) by_group[verify::group_of(c)].push_back(c);

  std::size_t done = 0;
  for (const auto& g : cmp.groups) {
    const auto& gc = by_group[g];
    progress(fmt::format("timing [{}/{}] {} ({} cases)", ++done, cmp.groups.size(), g, gc.size()));
    std::vector<io::Case> rounded;
    for (const auto& c : gc) rounded.push_back(io::round_to_float(c));
    for (const Method* m : methods) {
      if (!m->supports(gc.front().kind)) continue;
      Row row;
      row.method = m->name;
      row.group = g;
      row.kind = gc.front().kind;
      row.precision = m->precision;
      row.stats = cmp.stats.at({m->name, g});
      row.promise = m->promise(row.kind);
      row.ns_per_case = ns_per_case(*m, m->precision == Precision::float32 ? rounded : gc);
      rep.rows.push_back(std::move(row));
    }
  }

  std::vector<bool> pair_only;  // per point: the method answered pairs alone
  for (const Method* m : methods) {
    Point p;
    p.method = m->name;
    double weighted = 0;
    std::size_t n = 0;
    verify::Stats total;
    // A method that answers rays and pairs (exact, certified) is placed by its ray cases: a pair costs
    // CGAL about 0.1 ms, and mixing the two would move its point by the share of pairs in the run.
    const bool has_ray_rows = std::any_of(rep.rows.begin(), rep.rows.end(), [&](const Row& r) {
      return r.method == m->name && r.kind != io::Kind::tritri;
    });
    for (const auto& r : rep.rows) {
      if (r.method != m->name) continue;
      if (has_ray_rows && r.kind == io::Kind::tritri) continue;
      weighted += r.ns_per_case * double(r.stats.cases);
      n += r.stats.cases;
      total.merge(r.stats);
    }
    if (n == 0) continue;
    pair_only.push_back(!has_ray_rows);
    p.ns_per_case = weighted / double(n);
    p.class_error_rate = total.class_error_rate();
    p.max_ulps = total.ulp_quantile(1.0);
    p.fallback_rate = double(total.fallbacks) / double(n);
    p.precision = m->precision;
    p.promised = total.promised;
    p.promise_broken = total.promise_broken;
    rep.points.push_back(p);
  }
  // The Pareto front among methods of rays, and apart among methods of pairs alone: a pair test is
  // no faster or slower alternative to a ray test.
  for (const bool pairs : {false, true}) {
    std::vector<std::size_t> idx;
    std::vector<double> time, err;
    for (std::size_t i = 0; i < rep.points.size(); ++i)
      if (pair_only[i] == pairs) idx.push_back(i), time.push_back(rep.points[i].ns_per_case),
                                 err.push_back(rep.points[i].class_error_rate);
    const auto front = pareto_front(time, err);
    for (std::size_t k = 0; k < idx.size(); ++k) rep.points[idx[k]].pareto = front[k];
  }
  return rep;
}

std::string to_csv(const Report& r) {
  std::string s =
      "method,family,kind,precision,cases,class_errors,false_hit,false_miss,wrong_hit_class,wrong_class,"
      "ulp_median,ulp_p99,ulp_max,ns_per_case,fallbacks\n";
  for (const auto& row : r.rows) {
    const auto& st = row.stats;
    s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{:.2f},{}\n", row.method, row.group, io::to_string(row.kind),
                     row.precision == Precision::float32 ? "float" : "double", st.cases, st.class_errors(),
                     st.false_hit, st.false_miss, st.wrong_hit_class, st.wrong_class, st.ulp_quantile(0.5),
                     st.ulp_quantile(0.99), st.ulp_quantile(1.0), row.ns_per_case, st.fallbacks);
  }
  return s;
}

std::string to_markdown(const Report& r) {
  std::string s = "# " + r.title + "\n\n";
  for (const auto& n : r.notes) s += "- " + n + "\n";
  s += "\nClass errors: *false hit* (exact says the ray does not touch the primitive), *false miss* "
       "(exact says it does), *wrong hit class* (both touch, different class, e.g. `interior` for `edge`), "
       "*other* (neither touches, different class, e.g. `miss` for `parallel`). t error in ulps of the method's "
       "own precision, over class-correct cases. Run time: median of repeated batches, every method in this "
       "run, through the same registry call. *Promise*: what the method promises on the kind (exact class, no "
       "false miss, t within N ulps), checked on every case: kept on all N cases, broken on B of N, or none made.\n\n";
  s += error_free_definition(r.ulp_tolerance) + "\n\n";
  s += "![error against run time](error_vs_time.svg)\n\n";
  if (!r.kernel_failures.empty()) {
    s += "## Kernel failures\n\nYour kernels crashed, hung, exited early or answered garbage on these cases "
         "(one case-file line each, the input as the kernel saw it); they count apart from class errors.\n\n```\n";
    for (const auto& [m, f] : r.kernel_failures) s += io::format_case(f.input) + "  # " + m + ": " + f.what + "\n";
    s += "```\n\n";
  }

  s += "## Summary per method\n\n| method | ns/case | class error rate | max t error (ulps) | fallback rate | Pareto | "
       "promise |\n|---|---:|---:|---:|---:|:---:|---|\n";
  for (const auto& p : r.points) {
    verify::Stats ps;
    ps.promised = p.promised, ps.promise_broken = p.promise_broken;
    s += fmt::format("| {} | {:.1f} | {:.4f}% | {} | {:.3f}% | {} | {} |\n", p.method, p.ns_per_case,
                     100 * p.class_error_rate, ulp_text(p.max_ulps, p.precision), 100 * p.fallback_rate,
                     p.pareto ? "yes" : "", promise_cell(ps));
  }
  if (const auto ps = promise_sentences(r.rows); !ps.empty()) {
    s += "\n## Promises\n\n";
    for (const auto& x : ps) s += "- " + x + "\n";
  }

  for (io::Kind k : io::kCaseKinds) {
    std::vector<const Row*> rows;
    for (const auto& row : r.rows)
      if (row.kind == k) rows.push_back(&row);
    if (rows.empty()) continue;
    s += fmt::format("\n## {}\n\n", io::to_string(k));
    // Per method over the kind.
    std::vector<std::string> methods;
    std::vector<std::string> groups;
    for (const Row* row : rows) {
      if (std::find(methods.begin(), methods.end(), row->method) == methods.end()) methods.push_back(row->method);
      if (std::find(groups.begin(), groups.end(), row->group) == groups.end()) groups.push_back(row->group);
    }
    // A pair's "hit" is "the triangles meet" (docs/tritri.md).
    const bool pairs = k == io::Kind::tritri;
    if (pairs)
      s += "Triangle pairs: a false meets is a pair called meeting that exact arithmetic finds disjoint, a false "
           "disjoint the other way round; `hit`/`miss` answers on pairs whose exact class is degenerate or invalid "
           "are not judged and not counted. A method that answers rays too is placed on the chart and in the summary "
           "by its ray cases alone; its pair rows are here.\n\n";
    s += fmt::format("| method | ns/case | cases | class errors | {} | {} | {} | other | "
                     "t ulps median | p99 | max | fallbacks | promise |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
                     pairs ? "false meets" : "false hit", pairs ? "false disjoint" : "false miss",
                     pairs ? "wrong class among meets" : "wrong hit class");
    std::map<std::string, std::pair<double, verify::Stats>> per_method;
    std::map<std::string, Precision> precision_of;
    for (const Row* row : rows) {
      auto& [ns, st] = per_method[row->method];
      ns += row->ns_per_case * double(row->stats.cases);
      st.merge(row->stats);
      precision_of[row->method] = row->precision;
    }
    for (const auto& m : methods) {
      const auto& [ns, st] = per_method[m];
      const Precision p = precision_of[m];
      s += fmt::format("| {} | {:.1f} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", m, ns / double(st.cases),
                       st.cases, st.class_errors(), st.false_hit, st.false_miss, st.wrong_hit_class, st.wrong_class,
                       ulp_text(st.ulp_quantile(0.5), p), ulp_text(st.ulp_quantile(0.99), p),
                       ulp_text(st.ulp_quantile(1.0), p), st.fallbacks, promise_cell(st));
    }
    s += "\n";
    std::string said;
    for (const auto& x : kind_sentences(k, r.rows, r.ulp_tolerance)) said += (said.empty() ? "" : " ") + x;
    s += said + "\n\nPer family, each cell: class errors / cases, and t followed by the largest t error in ulps.\n\n";
    // Per family detail: class errors and max ulps per method.
    s += "| family |";
    for (const auto& m : methods) s += " " + m + " |";
    s += "\n|---|";
    for (std::size_t i = 0; i < methods.size(); ++i) s += "---:|";
    s += "\n";
    for (const auto& g : groups) {
      s += "| " + g + " |";
      for (const auto& m : methods) {
        const Row* cell = nullptr;
        for (const Row* row : rows)
          if (row->group == g && row->method == m) cell = row;
        if (!cell) {
          s += " |";
          continue;
        }
        s += fmt::format(" {}/{} err, t {} |", cell->stats.class_errors(), cell->stats.cases,
                         ulp_text(cell->stats.ulp_quantile(1.0), cell->precision));
      }
      s += "\n";
    }
  }
  if (const auto ts = t_error_sentences(r.rows); !ts.empty()) {
    s += "\n## t errors that need a word\n\n";
    for (const auto& x : ts) s += "- " + x + "\n";
  }
  if (!r.reproducers.empty()) {
    s += "\n## Reproducers\n\n" + r.reproducers_intro + "\n\n```\n";
    for (const auto& x : r.reproducers) s += x + "\n";
    s += "```\n";
  }
  return s;
}

std::string write_report(const Report& r, const std::string& dir) {
  const std::pair<const char*, std::string> files[] = {
      {"report.md", to_markdown(r)}, {"report.csv", to_csv(r)}, {"error_vs_time.svg", to_svg(r)}};
  return write_files(dir, files);
}

std::string write_files(const std::string& dir, std::span<const std::pair<const char*, std::string>> files) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return dir + ": cannot create directory (" + ec.message() + ")";
  for (const auto& [name, text] : files) {
    const auto path = std::filesystem::path(dir) / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) return path.string() + ": cannot write";
  }
  return "";
}

}  // namespace rayproof::report
