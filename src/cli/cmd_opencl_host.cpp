/// rayproof opencl-host (hidden): the device process of `--opencl NAME=FILE` (docs/opencl.md).
/// Builds the user's file inside the wrapper on one OpenCL device, says `R` (ready, with the
/// device's description) or `E` (why not), then answers batches on stdin/stdout in the private
/// framing of methods/opencl_frames.h until its input ends. rayproof kills it when a batch runs
/// over the timeout (OpenCL cannot stop a running kernel) and starts another.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>
#include <vector>

#include "cli/commands.h"
#include "methods/opencl_frames.h"

#ifdef RAYPROOF_HAVE_OPENCL
#include "methods/opencl_device.h"
#endif

namespace rayproof::cli {

namespace {

struct HostOptions {
  std::string file, precision = "float", options;
  std::vector<std::string> kinds;
  int device = 0;
  bool contract_off = false;
  bool list = false;
  std::size_t max_cases = 0;  ///< the shared memory's capacity in cases
};

/// --list: the devices, one a line, or why there is none (status 3).
int list_devices_text() {
#ifndef RAYPROOF_HAVE_OPENCL
  fmt::print(stderr, "rayproof opencl-host: this rayproof was built without OpenCL (install ocl-icd-opencl-dev "
                     "opencl-headers and rebuild)\n");
  return 3;
#else
  auto devs = opencl::list_devices();
  if (auto* why = std::get_if<std::string>(&devs)) {
    fmt::print(stderr, "rayproof opencl-host: {}\n", *why);
    return 3;
  }
  fmt::print("{}", opencl::device_list_text(std::get<std::vector<opencl::DeviceInfo>>(devs)));
  return 0;
#endif
}

int run_opencl_host(const HostOptions& o) {
  if (o.list) return list_devices_text();
  // Dies with rayproof: a kernel spinning forever must not outlive the run that started it. (Not
  // PR_SET_PDEATHSIG: it fires when the spawning thread ends, and a restart may come from a worker.)
  const pid_t parent = ::getppid();
  std::thread([parent] {
    for (;;) {
      if (::getppid() != parent) ::_exit(3);
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
  }).detach();
  // The frames go to the original stdout; anything a driver prints to stdout goes to stderr.
  const int out = ::dup(1);
  ::dup2(2, 1);
#ifndef RAYPROOF_HAVE_OPENCL
  opencl::write_text_frame(out, 'E', "this rayproof was built without OpenCL (install ocl-icd-opencl-dev "
                                     "opencl-headers and rebuild)");
  (void)o;
  return 2;
#else
  using namespace opencl;
  std::ifstream in(o.file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) {
    write_text_frame(out, 'E', o.file + ": cannot read it");
    return 2;
  }
  std::vector<io::Kind> kinds;
  for (const auto& k : o.kinds) {
    auto kind = io::kind_from_string(k);
    if (!kind) {
      write_text_frame(out, 'E', "unknown kind " + k);
      return 2;
    }
    kinds.push_back(*kind);
  }
  WrapperOptions wo;
  wo.precision = o.precision == "double" ? Precision::float64 : Precision::float32;
  wo.contract_off = o.contract_off;
  const auto t0 = std::chrono::steady_clock::now();
  auto built = Program::build(o.device, wrapper_source(text.str(), o.file, kinds, wo), o.options, kinds, wo.precision);
  if (auto* why = std::get_if<std::string>(&built)) {
    write_text_frame(out, 'E', *why);
    return 2;
  }
  Program& prog = *std::get<std::unique_ptr<Program>>(built);
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const DeviceInfo& d = prog.device();
  const std::string ready = fmt::format("device\t{}\nfloat_denorms\t{}\nfloat_fma\t{}\nbuild_seconds\t{:.3f}\n",
                                        d.describe(), d.float_denorms ? 1 : 0, d.float_fma ? 1 : 0, build_s);
  if (!write_text_frame(out, 'R', ready)) return 2;

  const bool timing = std::getenv("RAYPROOF_OPENCL_TIMING") != nullptr;  // docs/opencl.md, "Speed"
  ShmLayout shm{o.max_cases, wo.precision == Precision::float64 ? sizeof(double) : sizeof(float)};
  void* base = ::mmap(nullptr, shm.bytes(), PROT_READ | PROT_WRITE, MAP_SHARED, 3, 0);
  if (base == MAP_FAILED) {
    write_text_frame(out, 'E', std::string("cannot map the shared memory: ") + std::strerror(errno));
    return 2;
  }
  auto* bytes = static_cast<unsigned char*>(base);
  for (;;) {
    FrameHeader h;
    BatchFrame b;
    if (!read_all(0, &h, sizeof h)) return 0;  // end of input: done
    if (h.tag != 'B' || h.bytes != sizeof b || !read_all(0, &b, sizeof b) || b.cases > o.max_cases || b.kind < 0 ||
        b.kind > 5) {
      write_text_frame(out, 'E', "bad frame from rayproof");
      return 2;
    }
    const auto kind = static_cast<io::Kind>(b.kind);
    const auto r0 = std::chrono::steady_clock::now();
    auto err = prog.run(kind, bytes + shm.in_offset(), b.cases, reinterpret_cast<std::int32_t*>(bytes + shm.code_offset()),
                        bytes + shm.out_offset());
    if (timing)
      fmt::print(stderr, "[opencl-host] {} cases: {:.3f} ms on the device (copies included)\n", b.cases,
                 std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count());
    if (err) {
      write_text_frame(out, 'E', "OpenCL device " + std::to_string(o.device) + ": " + *err);
      return 2;
    }
    if (!write_frame(out, 'A', &b.cases, sizeof b.cases)) return 2;
  }
#endif
}

}  // namespace

Run add_opencl_host(CLI::App& app) {
  auto o = std::make_shared<HostOptions>();
  auto* sub = app.add_subcommand("opencl-host", "The device process of --opencl (framed batches on stdin/stdout)");
  sub->group("");  // hidden: --opencl runs it
  sub->add_option("--file", o->file);
  sub->add_flag("--list", o->list, "List the OpenCL devices (the numbers of --device) and exit");
  sub->add_option("--device", o->device);
  sub->add_option("--precision", o->precision);
  sub->add_option("--kinds", o->kinds)->delimiter(',');
  sub->add_option("--options", o->options);
  sub->add_flag("--contract-off", o->contract_off);
  sub->add_option("--max-cases", o->max_cases);
  return [o] { return run_opencl_host(*o); };
}

}  // namespace rayproof::cli
