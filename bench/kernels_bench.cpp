/// ns per test of every triangle, sphere and box method, kernels called directly on arrays of
/// precomputed inputs (generic hits, generic misses, edge-heavy), then a table of ratios to `robust`
/// measured in the same run, with the certified filter's fallback rate beside it.
/// Run: kernels_bench [google-benchmark flags], e.g. --benchmark_min_time=0.2; with
/// --benchmark_repetitions=N the table takes the fastest repetition of each. Ratios come from core
/// cycles (perf_event_open) where the kernel allows it, else from CPU time.
#include <benchmark/benchmark.h>

#if defined(__linux__)
#include <linux/perf_event.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "rayproof/box_conservative.h"
#include "rayproof/certified/intersect.h"
#include "rayproof/certified_box.h"
#include "rayproof/certified_fma.h"
#include "rayproof/certified_quadric.h"
#include "rayproof/certified_triangle.h"
#include "rayproof/verify/exact.h"
#include "rayproof/quadric_stable.h"
#include "rayproof/triangle.h"
#include "rayproof/triangle_baldwin_weber.h"
#include "rayproof/triangle_plucker.h"
#include "rayproof/triangle_watertight.h"
#include "verify/exact_method.h"
#include "exact/fallback.h"

using namespace rayproof;

namespace {

constexpr std::size_t kN = 4096;
enum class Input { hit, miss, edge };
const char* name_of(Input i) { return i == Input::hit ? "generic_hit" : i == Input::miss ? "generic_miss" : "edge_heavy"; }

/// Float-exact inputs (every value a float), so float and double methods see the same case.
struct Rng {
  std::mt19937_64 g{12345};
  float u(float a = -1, float b = 1) { return std::uniform_real_distribution<float>(a, b)(g); }
  Vec3<float> v(float s = 1) { return {s * u(), s * u(), s * u()}; }
};

struct TriCase { Ray<float> ray; Triangle<float> tri; };
struct SphCase { Ray<float> ray; Sphere<float> s; };
struct BoxCase { Ray<float> ray; Box<float> b; };

std::vector<TriCase> tri_inputs(Input in) {
  Rng r;
  std::vector<TriCase> out;
  while (out.size() < kN) {
    const Triangle<float> t{r.v(), r.v(), r.v()};
    const Vec3<float> o = r.v(4);
    Vec3<float> target;
    if (in == Input::edge) target = t.p0 + 0.5f * (t.p1 - t.p0);  // edge midpoint (rounded to float)
    else {
      const float a = r.u(0, 1), b = r.u(0, 1);
      const float s = a + b > 1 ? 1 : 0;  // a point inside; misses step outside by 50%
      const float b1 = s ? 1 - a : a, b2 = s ? 1 - b : b;
      target = in == Input::hit ? t.p0 + b1 * (t.p1 - t.p0) + b2 * (t.p2 - t.p0)
                                : t.p0 + 1.5f * (t.p1 - t.p0) + 1.5f * (t.p2 - t.p0);
    }
    out.push_back({{o, target - o}, t});
  }
  return out;
}

std::vector<SphCase> sph_inputs(Input in) {
  Rng r;
  std::vector<SphCase> out;
  while (out.size() < kN) {
    const Sphere<float> s{r.v(), r.u(0.2f, 1)};
    const Vec3<float> o = r.v(6);
    const float k = in == Input::hit ? 0.5f : (in == Input::miss ? 2.0f : 1.0f);  // edge: tangent-ish
    const Vec3<float> side = normalize(cross(s.center - o, Vec3<float>{0.3f, 0.5f, 0.7f}));
    out.push_back({{o, s.center + (k * s.radius) * side - o}, s});
  }
  return out;
}

std::vector<BoxCase> box_inputs(Input in) {
  Rng r;
  std::vector<BoxCase> out;
  while (out.size() < kN) {
    const Vec3<float> c = r.v(), h{r.u(0.1f, 1), r.u(0.1f, 1), r.u(0.1f, 1)};
    const Box<float> b{c - h, c + h};
    const Vec3<float> o = r.v(6);
    const Vec3<float> target = in == Input::hit ? c : (in == Input::miss ? c + 3.0f * h : b.hi);  // edge: a corner
    out.push_back({{o, target - o}, b});
  }
  return out;
}

template <class T> Ray<T> rc(const Ray<float>& r) { return {r.o.cast<T>(), r.d.cast<T>()}; }
template <class T> Triangle<T> tc(const Triangle<float>& t) { return {t.p0.cast<T>(), t.p1.cast<T>(), t.p2.cast<T>()}; }

io::Case case_of(const Ray<double>& ray, std::initializer_list<double> prim, io::Kind k) {
  io::Case c{k, {}, {}, 0};
  std::size_t i = 0;
  for (double x : {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z}) c.v[i++] = x;
  for (double x : prim) c.v[i++] = x;
  return c;
}

/// Certified: filter, and the exact fallback when it cannot decide (counted).
std::map<std::string, std::pair<std::size_t, std::size_t>> g_fallback;  // (fallbacks, tests)

int certified_tri(const TriCase& c, std::size_t* fb) {
  const Ray<double> ray = rc<double>(c.ray);
  const Triangle<double> t = tc<double>(c.tri);
  if (auto h = certified::triangle(ray, t)) return is_hit(h->contact);
  if (fb) ++*fb;
  const auto& p = t;
  return is_hit(verify::exact_classify(case_of(ray, {p.p0.x, p.p0.y, p.p0.z, p.p1.x, p.p1.y, p.p1.z, p.p2.x, p.p2.y, p.p2.z},
                                               io::Kind::triangle)).contact);
}
int certified_sph(const SphCase& c, std::size_t* fb) {
  const Ray<double> ray = rc<double>(c.ray);
  const Sphere<double> s{c.s.center.cast<double>(), double(c.s.radius)};
  if (auto h = certified::sphere(ray, s)) return is_hit(h->contact);
  if (fb) ++*fb;
  return is_hit(verify::exact_classify(case_of(ray, {s.center.x, s.center.y, s.center.z, s.radius}, io::Kind::sphere)).contact);
}
int certified_box(const BoxCase& c, std::size_t* fb) {
  const Ray<double> ray = rc<double>(c.ray);
  const Box<double> b{c.b.lo.cast<double>(), c.b.hi.cast<double>()};
  if (auto h = certified::box(ray, b)) return is_hit(h->contact);
  if (fb) ++*fb;
  return is_hit(verify::exact_classify(case_of(ray, {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z}, io::Kind::box)).contact);
}

/// Core cycles spent in user space by this thread (Linux perf_event_open), or nothing where the kernel
/// does not allow it (then the table falls back to CPU time). Cycles, unlike time, do not move with the
/// clock frequency, which other tenants of a shared machine change from run to run.
class Cycles {
 public:
  Cycles() {
#if defined(__linux__)
    perf_event_attr a;
    std::memset(&a, 0, sizeof a);
    a.size = sizeof a;
    a.type = PERF_TYPE_HARDWARE;
    a.config = PERF_COUNT_HW_CPU_CYCLES;
    a.exclude_kernel = 1;
    a.exclude_hv = 1;
    fd_ = static_cast<int>(syscall(SYS_perf_event_open, &a, 0, -1, -1, 0));
#endif
  }
  ~Cycles() {
#if defined(__linux__)
    if (fd_ >= 0) close(fd_);
#endif
  }
  Cycles(const Cycles&) = delete;
  Cycles& operator=(const Cycles&) = delete;
  [[nodiscard]] std::optional<std::uint64_t> now() const {
#if defined(__linux__)
    std::uint64_t v = 0;
    if (fd_ >= 0 && read(fd_, &v, sizeof v) == static_cast<ssize_t>(sizeof v)) return v;
#endif
    return std::nullopt;
  }

 private:
  int fd_ = -1;
};

template <class Case, class F>
void add(const std::string& kind, Input in, const std::string& method, const std::vector<Case>& cases, F f) {
  const std::string name = kind + "/" + name_of(in) + "/" + method;
  benchmark::RegisterBenchmark(name.c_str(), [cases, f](benchmark::State& st) {
    const Cycles counter;
    std::uint64_t cycles = 0;
    bool counted = true;
    int hits = 0;
    for (auto _ : st) {
      const auto c0 = counter.now();
      for (const auto& c : cases) hits += f(c);
      benchmark::DoNotOptimize(hits);
      const auto c1 = counter.now();
      if (c0 && c1) cycles += *c1 - *c0;
      else counted = false;
    }
    st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations()) * static_cast<std::int64_t>(cases.size()));
    if (counted && st.iterations() > 0)
      st.counters["cycles"] = double(cycles) / double(st.iterations()) / double(cases.size());
  });
}

void register_all() {
  for (Input in : {Input::hit, Input::miss, Input::edge}) {
    const auto tri = tri_inputs(in);
    add("triangle", in, "float", tri, [](const TriCase& c) { return int(is_hit(intersect_moller_trumbore(c.ray, c.tri).contact)); });
    add("triangle", in, "double", tri, [](const TriCase& c) {
      return int(is_hit(intersect_moller_trumbore(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    add("triangle", in, "cramer-float", tri, [](const TriCase& c) { return int(is_hit(intersect_cramer(c.ray, c.tri).contact)); });
    add("triangle", in, "robust", tri, [](const TriCase& c) { return int(is_hit(intersect_watertight<float, double>(c.ray, c.tri).contact)); });
    add("triangle", in, "watertight-float", tri, [](const TriCase& c) { return int(is_hit(intersect_watertight<float, float>(c.ray, c.tri).contact)); });
    add("triangle", in, "robust-double", tri, [](const TriCase& c) {
      return int(is_hit(intersect_watertight<double, double>(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    add("triangle", in, "mt-double", tri, [](const TriCase& c) {
      return int(is_hit(intersect_moller_trumbore(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    std::vector<std::pair<Ray<float>, BaldwinWeberTriangle<float>>> bw;  // precomputed transforms
    for (const auto& c : tri) bw.push_back({c.ray, baldwin_weber_prepare(c.tri)});
    add("triangle", in, "baldwin-weber", bw, [](const auto& c) { return int(is_hit(intersect_baldwin_weber(c.first, c.second).contact)); });
    add("triangle", in, "plucker", tri, [](const TriCase& c) { return int(is_hit(intersect_plucker(c.ray, c.tri).contact)); });
    add("triangle", in, "certified", tri, [](const TriCase& c) { return certified_tri(c, nullptr); });
    // The typed library API (rayproof/certified/intersect.h: with barycentrics), the ground truth (rayproof/verify/exact.h, CGAL)
    // and the certified tier's exact fallback alone (src/exact/fallback.h, GMP): the cost of one fallback.
    add("triangle", in, "certified-api", tri, [](const TriCase& c) {
      return int(is_hit(certified::intersect(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    {  // the API's own fallback count (per thread)
      auto& fa = g_fallback[std::string("triangle/") + name_of(in) + "/api"];
      const std::uint64_t before = certified::fallback_count();
      for (const auto& c : tri) benchmark::DoNotOptimize(certified::intersect(rc<double>(c.ray), tc<double>(c.tri)));
      fa = {certified::fallback_count() - before, tri.size()};
    }
    add("triangle", in, "exact-api", tri, [](const TriCase& c) {
      return int(is_hit(exact::intersect(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    add("triangle", in, "fallback-api", tri, [](const TriCase& c) {
      return int(is_hit(certified::fallback::intersect(rc<double>(c.ray), tc<double>(c.tri)).contact));
    });
    auto& ft = g_fallback[std::string("triangle/") + name_of(in)];
    for (const auto& c : tri) certified_tri(c, &ft.first);
    ft.second = tri.size();

    const auto sph = sph_inputs(in);
    add("sphere", in, "float", sph, [](const SphCase& c) { return int(is_hit(intersect(c.ray, c.s).contact)); });
    add("sphere", in, "double", sph, [](const SphCase& c) {
      return int(is_hit(intersect(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}).contact));
    });
    add("sphere", in, "robust", sph, [](const SphCase& c) { return int(is_hit(intersect_stable(c.ray, c.s).contact)); });
    add("sphere", in, "robust-double", sph, [](const SphCase& c) {
      return int(is_hit(intersect_stable(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}).contact));
    });
    add("sphere", in, "certified", sph, [](const SphCase& c) { return certified_sph(c, nullptr); });
    add("sphere", in, "certified-api", sph, [](const SphCase& c) {
      return int(is_hit(certified::intersect(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}).contact));
    });
    {  // the API's own fallback count (per thread)
      auto& fa = g_fallback[std::string("sphere/") + name_of(in) + "/api"];
      const std::uint64_t before = certified::fallback_count();
      for (const auto& c : sph) benchmark::DoNotOptimize(certified::intersect(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}));
      fa = {certified::fallback_count() - before, sph.size()};
    }
    add("sphere", in, "exact-api", sph, [](const SphCase& c) {
      return int(is_hit(exact::intersect(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}).contact));
    });
    add("sphere", in, "fallback-api", sph, [](const SphCase& c) {
      return int(is_hit(certified::fallback::intersect(rc<double>(c.ray), Sphere<double>{c.s.center.cast<double>(), c.s.radius}).contact));
    });
    auto& fs = g_fallback[std::string("sphere/") + name_of(in)];
    for (const auto& c : sph) certified_sph(c, &fs.first);
    fs.second = sph.size();

    const auto box = box_inputs(in);
    add("box", in, "float", box, [](const BoxCase& c) { return int(is_hit(intersect(c.ray, c.b).contact)); });
    add("box", in, "double", box, [](const BoxCase& c) {
      return int(is_hit(intersect(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}).contact));
    });
    add("box", in, "robust", box, [](const BoxCase& c) { return int(is_hit(intersect_conservative(c.ray, c.b).contact)); });
    add("box", in, "robust-double", box, [](const BoxCase& c) {
      return int(is_hit(intersect_conservative(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}).contact));
    });
    add("box", in, "certified", box, [](const BoxCase& c) { return certified_box(c, nullptr); });
    add("box", in, "certified-api", box, [](const BoxCase& c) {
      return int(is_hit(certified::intersect(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}).contact));
    });
    {  // the API's own fallback count (per thread)
      auto& fa = g_fallback[std::string("box/") + name_of(in) + "/api"];
      const std::uint64_t before = certified::fallback_count();
      for (const auto& c : box) benchmark::DoNotOptimize(certified::intersect(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}));
      fa = {certified::fallback_count() - before, box.size()};
    }
    add("box", in, "exact-api", box, [](const BoxCase& c) {
      return int(is_hit(exact::intersect(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}).contact));
    });
    add("box", in, "fallback-api", box, [](const BoxCase& c) {
      return int(is_hit(certified::fallback::intersect(rc<double>(c.ray), Box<double>{c.b.lo.cast<double>(), c.b.hi.cast<double>()}).contact));
    });
    auto& fb = g_fallback[std::string("box/") + name_of(in)];
    for (const auto& c : box) certified_box(c, &fb.first);
    fb.second = box.size();
  }
}

/// Console output as usual, plus CPU ns and core cycles per test of every run for the ratio table
/// (CPU time or cycles, not wall time: the ratios stay meaningful when other processes share the
/// machine).
class Collector : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> ns;      ///< "kind/input/method" -> CPU ns per test
  std::map<std::string, double> cycles;  ///< the same in core cycles, where counted
  void ReportRuns(const std::vector<Run>& runs) override {
    // With --benchmark_repetitions=N, the fastest repetition (the least disturbed by other processes).
    auto keep_min = [](std::map<std::string, double>& m, const std::string& k, double v) {
      const auto [it, fresh] = m.try_emplace(k, v);
      if (!fresh && v < it->second) it->second = v;
    };
    for (const auto& r : runs)
      if (r.run_type == Run::RT_Iteration && r.iterations > 0) {
        keep_min(ns, r.run_name.str(), r.cpu_accumulated_time * 1e9 / double(r.iterations) / double(kN));
        if (const auto c = r.counters.find("cycles"); c != r.counters.end()) keep_min(cycles, r.run_name.str(), c->second);
      }
    ConsoleReporter::ReportRuns(runs);
  }
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  register_all();
  Collector rep;
  benchmark::RunSpecifiedBenchmarks(&rep);
  // Ratios from core cycles when every run was counted, else from CPU time.
  const bool use_cycles = !rep.cycles.empty() && rep.cycles.size() == rep.ns.size();
  const auto& cost = use_cycles ? rep.cycles : rep.ns;
  std::printf("\n%-10s %-13s %-17s %9s %9s %9s %s\n", "kind", "input", "method", "cpu ns", "cycles", "x robust", "fallbacks");
  for (const auto& [name, t] : rep.ns) {
    const auto a = name.find('/'), b = name.find('/', a + 1);
    const std::string group = name.substr(0, b), method = name.substr(b + 1);
    const auto robust = cost.find(group + "/robust");
    const auto mine = cost.find(name);
    const double ratio = robust == cost.end() || mine == cost.end() ? 0.0 : mine->second / robust->second;
    std::string fb;
    if (method == "certified" || method == "certified-api") {
      const auto& f = g_fallback[method == "certified" ? group : group + "/api"];
      fb = std::to_string(f.first) + "/" + std::to_string(f.second);
    }
    const auto cyc = rep.cycles.find(name);
    std::printf("%-10s %-13s %-17s %9.2f %9.1f %9.2f %s\n", name.substr(0, a).c_str(), name.substr(a + 1, b - a - 1).c_str(),
                method.c_str(), t, cyc == rep.cycles.end() ? 0.0 : cyc->second, ratio, fb.c_str());
  }
  std::printf("\nx robust: ratio of %s per test, measured in this run%s\n", use_cycles ? "core cycles" : "CPU time",
              use_cycles ? "" : " (no cycle counter: perf_event_open refused)");
  std::printf("\ncertified t of triangles and spheres: %s (RAYPROOF_CERTIFIED_NO_FMA=1 selects the x87 path)\n",
              certified::dd::available() ? "double-double with hardware FMA" : "x87 extended precision");
  benchmark::Shutdown();
  return 0;
}
