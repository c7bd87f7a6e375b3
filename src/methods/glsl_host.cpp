/// `rayproof glsl-host`: the child process of a --glsl method (methods/glsl_kernel.h). It owns the
/// Vulkan device; the parent kills it when a dispatch hangs. Frames: glsl_kernel.cpp.
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdint>
#include <string>
#include <vector>

#include "methods/glsl_kernel.h"
#include "methods/glsl_source.h"
#include "methods/glsl_vulkan.h"

namespace rayproof {

namespace {

bool put(const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = ::write(1, p, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w, n -= std::size_t(w);
  }
  return true;
}

bool get(void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::read(0, p, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r, n -= std::size_t(r);
  }
  return true;
}

bool put_text(std::uint32_t status, const std::string& text) {
  const std::array<std::uint32_t, 2> head{status, static_cast<std::uint32_t>(text.size())};
  return put(head.data(), sizeof head) && put(text.data(), text.size());
}

}  // namespace

int run_glsl_host(const std::string& file, Precision precision, int device, bool no_contraction) {
  glsl::RunnerSpec spec;
  spec.file = file;
  spec.precision = precision;
  spec.device = device;
  spec.no_contraction = no_contraction;
  auto made = glsl::Runner::create(spec);
  if (auto* why = std::get_if<std::string>(&made)) {
    (void)put_text(1, *why);
    return 2;
  }
  glsl::Runner& runner = *std::get<std::unique_ptr<glsl::Runner>>(made);
  std::string kinds;
  for (io::Kind k : runner.kinds()) kinds += (kinds.empty() ? "" : ",") + std::string(io::to_string(k));
  if (!put_text(0, "kinds\t" + kinds + "\ndevice\t" + runner.info().describe() + "\nsubnormals\t" +
                       runner.info().subnormals(precision) + "\n"))
    return 2;
  const std::size_t real = precision == Precision::float64 ? sizeof(double) : sizeof(float);
  std::vector<unsigned char> in, out;
  for (;;) {
    std::array<std::uint32_t, 2> head{};
    if (!get(head.data(), sizeof head)) return 0;  // the parent went away
    if (head[0] == 0xffffffffu || head[0] > 5 || head[1] > runner.max_cases()) return 0;
    const std::size_t n = head[1];
    in.resize(n * glsl::kInReals * real);
    out.assign(n * glsl::kOutReals * real, 0);
    if (!get(in.data(), in.size())) return 0;
    const std::string why = runner.run(static_cast<io::Kind>(head[0]), in.data(), n, out.data());
    if (!why.empty()) {
      (void)put_text(1, why);
      return 3;
    }
    const std::uint32_t ok = 0;
    if (!put(&ok, sizeof ok) || !put(out.data(), out.size())) return 0;
  }
}

}  // namespace rayproof
