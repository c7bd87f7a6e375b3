#include "methods/opencl_kernel.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <vector>

#include <fmt/core.h>

#include "methods/child_process.h"
#include "methods/opencl_frames.h"
#include "methods/opencl_wrapper.h"


namespace rayproof {

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kMaxKept = 10000;  // failures kept between two takes

using Child = proc::Child;

struct State {
  std::string name, file, host;
  Precision precision = Precision::float32;
  std::vector<io::Kind> kinds;
  OpenclOptions opt;
  std::mutex mu;
  Child ch;
  OpenclDeviceReport report;
  std::vector<KernelFailure> failures;
  std::size_t bad_batches = 0;
  bool dropped = false;
  bool timing = std::getenv("RAYPROOF_OPENCL_TIMING") != nullptr;  // docs/opencl.md, "Speed"
  int shm_fd = -1;  // the cases and answers (opencl::ShmLayout), shared with every device process
  unsigned char* shm = nullptr;
  opencl::ShmLayout layout;

  ~State();
};

using proc::close_fd;

/// Ends the child: SIGKILL unless `gently` (then its input is closed and it exits by itself).
/// Gives its status text.
std::string end_child(Child& ch, bool gently) { return proc::end(ch, !gently); }

State::~State() {
  if (ch.pid >= 0) {
    // A child between batches exits at the end of its input; one cannot be running a batch here.
    end_child(ch, true);
  }
  if (shm) ::munmap(shm, layout.bytes());
  if (shm_fd >= 0) ::close(shm_fd);
}

enum class Read { ok, timeout, eof };

/// Reads n bytes before the deadline (a broken pipe or a poll error reads as the end).
Read read_until(int fd, void* p, std::size_t n, Clock::time_point deadline) {
  switch (proc::read_all(fd, p, n, deadline)) {
    case proc::Io::ok: return Read::ok;
    case proc::Io::timeout: return Read::timeout;
    default: return Read::eof;
  }
}

/// Reads one frame before the deadline; `payload` gets its bytes.
Read read_frame(int fd, opencl::FrameHeader& h, std::string& payload, Clock::time_point deadline) {
  if (Read r = read_until(fd, &h, sizeof h, deadline); r != Read::ok) return r;
  if (h.bytes > (std::uint64_t{1} << 34)) return Read::eof;
  payload.resize(h.bytes);
  return read_until(fd, payload.data(), payload.size(), deadline);
}

std::string precision_word(Precision p) { return p == Precision::float64 ? "double" : "float"; }

/// Starts the device process and waits for it to be ready. A message when it is not.
std::optional<std::string> start(State& st) {
  if (st.shm_fd < 0) {
    st.layout = opencl::ShmLayout{st.opt.max_batch, st.precision == Precision::float64 ? sizeof(double) : sizeof(float)};
    st.shm_fd = ::memfd_create("rayproof-opencl", MFD_CLOEXEC);
    if (st.shm_fd < 0) return std::string("memfd_create: ") + std::strerror(errno);
    if (::ftruncate(st.shm_fd, static_cast<off_t>(st.layout.bytes())) != 0)
      return std::string("ftruncate of the shared memory: ") + std::strerror(errno);
    void* p = ::mmap(nullptr, st.layout.bytes(), PROT_READ | PROT_WRITE, MAP_SHARED, st.shm_fd, 0);
    if (p == MAP_FAILED) return std::string("mmap of the shared memory: ") + std::strerror(errno);
    st.shm = static_cast<unsigned char*>(p);
  }
  std::vector<std::string> args{st.host, "opencl-host", "--file", st.file, "--device", std::to_string(st.opt.device),
                                "--precision", precision_word(st.precision)};
  std::string kinds;
  for (io::Kind k : st.kinds) kinds += (kinds.empty() ? "" : ",") + std::string(io::to_string(k));
  args.push_back("--kinds=" + kinds);
  args.push_back("--max-cases=" + std::to_string(st.opt.max_batch));
  if (st.opt.cl_options) args.push_back("--options=" + *st.opt.cl_options);
  if (st.opt.contract_off) args.push_back("--contract-off");
  proc::SpawnOptions so;
  so.fd3 = st.shm_fd;
  if (auto why = proc::spawn(st.host, args, so, st.ch); !why.empty()) return why + " (the OpenCL device process)";
  opencl::FrameHeader h;
  std::string payload;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(st.opt.build_timeout_seconds));
  const Read r = read_frame(st.ch.from, h, payload, deadline);
  if (r == Read::timeout) {
    end_child(st.ch, false);
    return fmt::format("the OpenCL build did not finish in {} s (the device process was killed)",
                       st.opt.build_timeout_seconds);
  }
  if (r == Read::eof) {
    const std::string how = end_child(st.ch, true);
    return fmt::format("the OpenCL device process {} before it was ready{}", how,
                       how.find("status 127") != std::string::npos
                           ? " (is libOpenCL missing? apt-get install ocl-icd-opencl-dev pocl-opencl-icd)"
                           : "");
  }
  if (h.tag == 'E') {
    end_child(st.ch, true);
    return payload;
  }
  if (h.tag != 'R') {
    end_child(st.ch, false);
    return "the OpenCL device process answered garbage";
  }
  std::istringstream lines(payload);
  for (std::string line; std::getline(lines, line);) {
    const auto tab = line.find('\t');
    if (tab == std::string::npos) continue;
    const std::string key = line.substr(0, tab), value = line.substr(tab + 1);
    if (key == "device") st.report.device = value;
    if (key == "float_denorms") st.report.float_denorms = value == "1";
    if (key == "float_fma") st.report.float_fma = value == "1";
    if (key == "build_seconds") st.report.build_seconds = std::atof(value.c_str());
  }
  return std::nullopt;
}

void add_failure(State& st, std::string what, const io::Case& c) {
  if (st.failures.size() < kMaxKept) st.failures.push_back({std::move(what), c});
}

/// A batch that did not come back: every case answered error, each reported; perhaps the end of
/// the kernel.
void lose_batch(State& st, std::span<const io::Case> in, const std::string& what) {
  for (const auto& c : in)
    add_failure(st, fmt::format("{} (a batch of {} {} cases, all answered error; which of them is to blame is not "
                                "known)", what, in.size(), io::to_string(in.front().kind)), c);
  if (++st.bad_batches >= st.opt.max_timeouts && !st.dropped) {
    st.dropped = true;
    fmt::print(stderr, "rayproof: OpenCL kernel {}: {} batches timed out or crashed: dropped from the run; its "
                       "remaining cases count as kernel failures\n", st.name, st.bad_batches);
  }
}

/// One launch's worth of cases of one kind, on the device process (started if need be).
void run_chunk(State& st, std::span<const io::Case> in, std::span<io::CaseResult> out) {
  for (auto& r : out) r = io::CaseResult{Contact::error};
  if (st.dropped || in.empty()) return;
  if (st.ch.pid < 0) {
    if (auto err = start(st)) {
      lose_batch(st, in, "could not restart the OpenCL device process: " + *err);
      return;
    }
  }
  const io::Kind kind = in.front().kind;
  const std::size_t nf = static_cast<std::size_t>(opencl::fields(kind));
  const auto tfill = Clock::now();
  if (st.precision == Precision::float64) {
    auto* v = reinterpret_cast<double*>(st.shm + st.layout.in_offset());
    for (std::size_t i = 0; i < in.size(); ++i) std::copy_n(in[i].v.begin(), nf, v + i * nf);
  } else {
    auto* v = reinterpret_cast<float*>(st.shm + st.layout.in_offset());
    for (std::size_t i = 0; i < in.size(); ++i)
      for (std::size_t j = 0; j < nf; ++j) v[i * nf + j] = static_cast<float>(in[i].v[j]);
  }
  const opencl::BatchFrame bf{static_cast<std::int32_t>(kind), static_cast<std::uint32_t>(in.size())};
  opencl::FrameHeader h;
  const auto t0 = Clock::now();
  std::string payload;
  Read r = Read::eof;
  if (opencl::write_frame(st.ch.to, 'B', &bf, sizeof bf)) {
    const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(st.opt.timeout_seconds));
    r = read_frame(st.ch.from, h, payload, deadline);
  }
  if (r == Read::timeout) {
    end_child(st.ch, false);
    lose_batch(st, in, fmt::format("timed out: no answer after {} s on {} (OpenCL cannot stop a running kernel: "
                                   "rayproof killed the device process and builds the kernel again for the next "
                                   "batch)", st.opt.timeout_seconds, st.report.device));
    return;
  }
  if (r == Read::eof) {
    const std::string how = end_child(st.ch, true);
    lose_batch(st, in, fmt::format("the OpenCL device process {} while running the kernel on {}", how, st.report.device));
    return;
  }
  if (h.tag == 'E') {
    end_child(st.ch, true);
    lose_batch(st, in, payload);
    return;
  }
  if (h.tag != 'A' || payload.size() != sizeof bf.cases || std::memcmp(payload.data(), &bf.cases, sizeof bf.cases) != 0) {
    end_child(st.ch, false);
    lose_batch(st, in, "the OpenCL device process answered garbage");
    return;
  }
  const auto tanswer = Clock::now();
  const auto* codes = reinterpret_cast<const std::int32_t*>(st.shm + st.layout.code_offset());
  const unsigned char* o = st.shm + st.layout.out_offset();
  for (std::size_t i = 0; i < in.size(); ++i) {
    opencl::RawAnswer raw{codes[i], 0, 0, 0};
    if (st.precision == Precision::float64) {
      const auto* d = reinterpret_cast<const double*>(o) + 3 * i;
      raw.t = d[0], raw.b1 = d[1], raw.b2 = d[2];
    } else {
      const auto* f = reinterpret_cast<const float*>(o) + 3 * i;
      raw.t = f[0], raw.b1 = f[1], raw.b2 = f[2];
    }
    auto res = opencl::to_result(kind, raw);
    if (auto* ok = std::get_if<io::CaseResult>(&res)) out[i] = *ok;
    else add_failure(st, std::get<std::string>(res), in[i]);
  }
  if (st.timing)
    fmt::print(stderr, "[opencl] {} cases: {:.3f} ms in all, {:.3f} ms until the answers came\n", in.size(),
               std::chrono::duration<double, std::milli>(Clock::now() - tfill).count(),
               std::chrono::duration<double, std::milli>(tanswer - tfill).count());
}

void run_batch(State& st, std::span<const io::Case> in, std::span<io::CaseResult> out) {
  std::lock_guard lock(st.mu);
  // Per kind, in launches of at most max_batch cases.
  for (io::Kind k : io::kAllKinds) {
    std::vector<std::size_t> idx;
    for (std::size_t i = 0; i < in.size(); ++i) {
      if (in[i].kind != k) continue;
      if (std::find(st.kinds.begin(), st.kinds.end(), k) == st.kinds.end()) out[i] = io::CaseResult{Contact::error};
      else idx.push_back(i);
    }
    if (idx.empty()) continue;
    const bool contiguous = idx.back() - idx.front() + 1 == idx.size();
    for (std::size_t b = 0; b < idx.size(); b += st.opt.max_batch) {
      const std::size_t e = std::min(idx.size(), b + st.opt.max_batch);
      if (contiguous) {
        run_chunk(st, in.subspan(idx[b], e - b), out.subspan(idx[b], e - b));
        continue;
      }
      std::vector<io::Case> part;
      for (std::size_t j = b; j < e; ++j) part.push_back(in[idx[j]]);
      std::vector<io::CaseResult> got(part.size());
      run_chunk(st, part, got);
      for (std::size_t j = b; j < e; ++j) out[idx[j]] = got[j - b];
    }
  }
}

bool good_name(std::string_view s) {
  if (s.empty() || s.size() > 64) return false;
  return std::all_of(s.begin(), s.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '.' || ch == '+' || ch == '-';
  });
}

}  // namespace

std::variant<Method, std::string> make_opencl_method(std::string_view spec_in, const std::string& host,
                                                     const OpenclOptions& opt, OpenclDeviceReport* report) {
  const std::string spec(spec_in);
  const std::string where = "--opencl " + spec;
  const auto eq = spec.find('=');
  std::string head = eq == std::string::npos ? std::string() : spec.substr(0, eq);
  const std::string file = eq == std::string::npos ? spec : spec.substr(eq + 1);
  if (file.empty()) return where + ": no FILE (NAME=FILE)";
  auto st = std::make_shared<State>();
  st->opt = opt;
  st->opt.max_batch = std::max<std::size_t>(opt.max_batch, 1);
  st->host = host;
  // NAME[:PRECISION[:KINDS]]
  std::vector<std::string> parts;
  for (std::size_t at = 0;;) {
    const auto colon = head.find(':', at);
    parts.push_back(head.substr(at, colon == std::string::npos ? std::string::npos : colon - at));
    if (colon == std::string::npos) break;
    at = colon + 1;
  }
  st->name = eq == std::string::npos ? std::filesystem::path(file).stem().string() : parts[0];
  if (!good_name(st->name)) return where + ": bad NAME '" + st->name + "' (1 to 64 characters of A-Z a-z 0-9 _ . + -)";
  if (parts.size() > 3) return where + ": too many ':' (NAME, NAME:PRECISION or NAME:PRECISION:KIND,KIND=FILE)";
  if (parts.size() >= 2) {
    if (parts[1] == "double") st->precision = Precision::float64;
    else if (parts[1] != "float") return where + ": precision '" + parts[1] + "' (float or double)";
  }

  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return "opencl " + file + ": no such file";
  if (!std::filesystem::is_regular_file(file, ec)) return "opencl " + file + ": not a regular file";
  std::ifstream f(file, std::ios::binary);
  std::stringstream text;
  text << f.rdbuf();
  if (!f) return "opencl " + file + ": cannot read it";
  const std::string source = text.str();
  if (source.find('\0') != std::string::npos) return "opencl " + file + ": a binary file, not OpenCL C source";
  const auto defined = opencl::kinds_defined(source);
  if (parts.size() == 3) {
    for (std::size_t at = 0; at <= parts[2].size();) {
      const auto comma = std::min(parts[2].find(',', at), parts[2].size());
      const std::string k = parts[2].substr(at, comma - at);
      auto kind = io::kind_from_string(k);
      if (!kind) return where + ": unknown kind '" + k + "' (plane sphere ellipsoid triangle box disk)";
      if (*kind == io::Kind::tritri)
        return where + ": kind tritri (two triangles) has no OpenCL kernels: they answer the ray kinds "
                       "(plane sphere ellipsoid triangle box disk)";
      if (std::find(defined.begin(), defined.end(), *kind) == defined.end())
        return "opencl " + file + ": declares kind " + k + " but defines no function " + opencl::function_name(*kind);
      st->kinds.push_back(*kind);
      at = comma + 1;
    }
  } else {
    st->kinds = defined;
  }
  if (st->kinds.empty())
    return "opencl " + file + ": defines none of the functions rayproof_plane, rayproof_sphere, rayproof_ellipsoid, "
           "rayproof_triangle, rayproof_box, rayproof_disk (docs/opencl.md gives their signatures)";
  std::sort(st->kinds.begin(), st->kinds.end());
  st->kinds.erase(std::unique(st->kinds.begin(), st->kinds.end()), st->kinds.end());
  st->file = std::filesystem::absolute(file, ec).string();
  if (host.empty()) return where + ": cannot find this rayproof's executable to run the device process";
  ::signal(SIGPIPE, SIG_IGN);  // a device process that dies while rayproof writes must not kill rayproof
  if (auto err = start(*st)) return "opencl " + file + ": " + *err;
  if (report) *report = st->report;

  Method m;
  m.name = st->name;
  m.precision = st->precision;
  m.kinds = st->kinds;
  m.summary = fmt::format("OpenCL C {} ({}) on OpenCL device {}: {}; build options: {}", file,
                          precision_word(st->precision), opt.device, st->report.device,
                          opt.cl_options ? "'" + *opt.cl_options + "'" : std::string("the device's defaults"));
  m.classify = [st](const io::Case& c) {
    io::CaseResult r;
    run_batch(*st, std::span<const io::Case>(&c, 1), std::span<io::CaseResult>(&r, 1));
    return r;
  };
  m.classify_batch = [st](std::span<const io::Case> in, std::span<io::CaseResult> out) { run_batch(*st, in, out); };
  m.take_failures = [st] {
    std::vector<KernelFailure> out;
    std::lock_guard lock(st->mu);
    out.swap(st->failures);
    return out;
  };
  return m;
}

}  // namespace rayproof
