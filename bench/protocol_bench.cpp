// Throughput of the --exec line protocol (docs/kernel_protocol.md): rayproof streams case lines to a
// trivial C kernel (bench/miss_kernel.c, `miss` to every line) and reads its answers. Prints cases/s
// for the whole round trip and for rayproof's formatting alone. Not a test: numbers depend on the
// machine and its load.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>
#include <vector>

#include "gen/families.h"
#include "io/case_file.h"
#include "methods/exec_kernel.h"

using namespace rayproof;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
/// CPU seconds (user + system) of this process so far: rayproof's side of the protocol.
double cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}
}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  std::printf("protocol_bench: %zu cases per batch, kernel %s\n", n, MISS_KERNEL);
  for (const char* family : {"tri_generic", "sph_generic", "tri_edge"}) {
    const auto cases = gen::generate(*gen::find_family(family), n, 1, gen::Precision::float64);
    const auto kind = std::string(io::to_string(cases[0].kind));
    auto made = make_exec_method("miss:double:" + kind + "=" + MISS_KERNEL);
    if (auto* e = std::get_if<std::string>(&made)) {
      std::fprintf(stderr, "protocol_bench: %s\n", e->c_str());
      return 1;
    }
    const Method& m = std::get<Method>(made);
    std::vector<io::CaseResult> out(cases.size());
    double best = 1e300, best_cpu = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpu_seconds();
      m.classify_many(cases, out);
      best = std::min(best, seconds_since(t0));
      best_cpu = std::min(best_cpu, cpu_seconds() - c0);
    }
    std::size_t misses = 0;
    for (const auto& r : out) misses += r.contact == Contact::miss;
    std::string buf;
    std::size_t bytes = 0;
    const auto t1 = std::chrono::steady_clock::now();
    for (const auto& c : cases) {
      io::append_case_line(buf, c);
      if (buf.size() > (1 << 16)) bytes += buf.size(), buf.clear();
    }
    bytes += buf.size();
    const double fmt_s = seconds_since(t1);
    std::printf("%-12s round trip: %9.0f cases/s wall (%.1f MB/s of case lines), %9.0f cases per CPU-second of "
                "rayproof's side; formatting alone: %9.0f cases/s (best of 3; %zu of %zu answered miss)\n",
                family, double(n) / best, double(bytes) / best / 1e6, double(n) / best_cpu, double(n) / fmt_s, misses,
                n);
    if (misses != n || !m.take_failures().empty()) {
      std::fprintf(stderr, "protocol_bench: the kernel did not answer every case\n");
      return 1;
    }
  }
  return 0;
}
