#include "methods/opencl_device.h"

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <map>

namespace rayproof::opencl {

namespace {

constexpr cl_int kPlatformNotFound = -1001;  // CL_PLATFORM_NOT_FOUND_KHR: the ICD loader found no driver

constexpr const char* kPackages =
    "install an OpenCL driver: on Debian `apt-get install ocl-icd-opencl-dev pocl-opencl-icd` (pocl: the CPU as an "
    "OpenCL device), or your GPU vendor's OpenCL ICD";

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  std::size_t n = 0;
  if (clGetPlatformInfo(p, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return "?";
  std::string s(n, '\0');
  if (clGetPlatformInfo(p, what, n, s.data(), nullptr) != CL_SUCCESS) return "?";
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string device_string(cl_device_id d, cl_device_info what) {
  std::size_t n = 0;
  if (clGetDeviceInfo(d, what, 0, nullptr, &n) != CL_SUCCESS || n == 0) return "?";
  std::string s(n, '\0');
  if (clGetDeviceInfo(d, what, n, s.data(), nullptr) != CL_SUCCESS) return "?";
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

struct Found {
  DeviceInfo info;
  cl_device_id id = nullptr;
};

std::variant<std::vector<Found>, std::string> find_devices() {
  cl_uint np = 0;
  const cl_int rc = clGetPlatformIDs(0, nullptr, &np);
  if (rc == kPlatformNotFound || np == 0)
    return std::string("no OpenCL platform found: ") + kPackages;
  if (rc != CL_SUCCESS) return fmt::format("clGetPlatformIDs failed (error {}): {}", rc, kPackages);
  std::vector<cl_platform_id> ps(np);
  clGetPlatformIDs(np, ps.data(), nullptr);
  std::vector<Found> out;
  for (cl_platform_id p : ps) {
    cl_uint nd = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS || nd == 0) continue;
    std::vector<cl_device_id> ds(nd);
    clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, nd, ds.data(), nullptr);
    for (cl_device_id d : ds) {
      Found f;
      f.id = d;
      f.info.platform = platform_string(p, CL_PLATFORM_NAME);
      f.info.platform_version = platform_string(p, CL_PLATFORM_VERSION);
      f.info.name = device_string(d, CL_DEVICE_NAME);
      f.info.version = device_string(d, CL_DEVICE_VERSION);
      f.info.driver_version = device_string(d, CL_DRIVER_VERSION);
      cl_device_type type = 0;
      clGetDeviceInfo(d, CL_DEVICE_TYPE, sizeof type, &type, nullptr);
      f.info.type = (type & CL_DEVICE_TYPE_GPU) ? "gpu" : (type & CL_DEVICE_TYPE_CPU) ? "cpu"
                    : (type & CL_DEVICE_TYPE_ACCELERATOR) ? "accelerator" : "other";
      cl_device_fp_config sf = 0, df = 0;
      clGetDeviceInfo(d, CL_DEVICE_SINGLE_FP_CONFIG, sizeof sf, &sf, nullptr);
      if (clGetDeviceInfo(d, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof df, &df, nullptr) != CL_SUCCESS) df = 0;
      f.info.float_denorms = (sf & CL_FP_DENORM) != 0;
      f.info.float_fma = (sf & CL_FP_FMA) != 0;
      const std::string ext = device_string(d, CL_DEVICE_EXTENSIONS);
      f.info.fp64 = df != 0 || ext.find("cl_khr_fp64") != std::string::npos;
      out.push_back(std::move(f));
    }
  }
  if (out.empty()) return fmt::format("{} OpenCL platform(s) but no device: {}", np, kPackages);
  return out;
}

}  // namespace

std::string DeviceInfo::describe() const {
  return fmt::format("{} ({}; platform {}, {}; driver {})", name, type, platform, version, driver_version);
}

std::variant<std::vector<DeviceInfo>, std::string> list_devices() {
  auto found = find_devices();
  if (auto* why = std::get_if<std::string>(&found)) return *why;
  std::vector<DeviceInfo> out;
  for (auto& f : std::get<std::vector<Found>>(found)) out.push_back(f.info);
  return out;
}

std::string device_list_text(const std::vector<DeviceInfo>& devices) {
  std::string s;
  for (std::size_t i = 0; i < devices.size(); ++i) s += fmt::format("  {}: {}\n", i, devices[i].describe());
  return s;
}

struct Program::Impl {
  DeviceInfo info;
  Precision precision = Precision::float32;
  cl_device_id device = nullptr;
  cl_context context = nullptr;
  cl_command_queue queue = nullptr;
  cl_program program = nullptr;
  std::map<io::Kind, cl_kernel> kernels;
  std::size_t local = 64;
  cl_mem in = nullptr, code = nullptr, out = nullptr;
  std::size_t capacity = 0;  // cases the buffers hold

  ~Impl() {
    for (auto& [k, kern] : kernels) clReleaseKernel(kern);
    for (cl_mem m : {in, code, out})
      if (m) clReleaseMemObject(m);
    if (program) clReleaseProgram(program);
    if (queue) clReleaseCommandQueue(queue);
    if (context) clReleaseContext(context);
  }

  std::size_t real_size() const { return precision == Precision::float64 ? sizeof(double) : sizeof(float); }

  std::optional<std::string> reserve(std::size_t cases) {
    if (cases <= capacity) return std::nullopt;
    const std::size_t want = std::max<std::size_t>(cases, 1024);
    for (cl_mem* m : {&in, &code, &out})
      if (*m) clReleaseMemObject(*m), *m = nullptr;
    cl_int e1 = 0, e2 = 0, e3 = 0;
    in = clCreateBuffer(context, CL_MEM_READ_ONLY, want * 15 * real_size(), nullptr, &e1);
    code = clCreateBuffer(context, CL_MEM_WRITE_ONLY, want * sizeof(cl_int), nullptr, &e2);
    out = clCreateBuffer(context, CL_MEM_WRITE_ONLY, want * 3 * real_size(), nullptr, &e3);
    if (e1 != CL_SUCCESS || e2 != CL_SUCCESS || e3 != CL_SUCCESS) {
      capacity = 0;
      return fmt::format("clCreateBuffer failed for {} cases (errors {} {} {})", want, e1, e2, e3);
    }
    capacity = want;
    return std::nullopt;
  }

  /// Enqueues kind's kernel over `n` cases (n = 0: a launch that runs no user code) and waits.
  std::optional<std::string> launch(io::Kind kind, std::size_t n) {
    cl_kernel k = kernels.at(kind);
    const cl_uint un = static_cast<cl_uint>(n);
    cl_int e = clSetKernelArg(k, 0, sizeof(cl_mem), &in);
    e |= clSetKernelArg(k, 1, sizeof(cl_mem), &code);
    e |= clSetKernelArg(k, 2, sizeof(cl_mem), &out);
    e |= clSetKernelArg(k, 3, sizeof(cl_uint), &un);
    if (e != CL_SUCCESS) return fmt::format("clSetKernelArg failed ({})", e);
    // A fixed work-group size: pocl compiles the kernel again for every new one.
    const std::size_t global = std::max<std::size_t>(1, (n + local - 1) / local) * local;
    e = clEnqueueNDRangeKernel(queue, k, 1, nullptr, &global, &local, 0, nullptr, nullptr);
    if (e != CL_SUCCESS) return fmt::format("clEnqueueNDRangeKernel failed ({})", e);
    e = clFinish(queue);
    if (e != CL_SUCCESS) return fmt::format("clFinish failed ({})", e);
    return std::nullopt;
  }
};

Program::Program(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Program::~Program() = default;

const DeviceInfo& Program::device() const { return impl_->info; }

std::variant<std::unique_ptr<Program>, std::string> Program::build(int index, const std::string& source,
                                                                   const std::string& options,
                                                                   const std::vector<io::Kind>& kinds,
                                                                   Precision precision) {
  auto found = find_devices();
  if (auto* why = std::get_if<std::string>(&found)) return *why;
  auto& devs = std::get<std::vector<Found>>(found);
  if (index < 0 || static_cast<std::size_t>(index) >= devs.size()) {
    std::vector<DeviceInfo> infos;
    for (auto& f : devs) infos.push_back(f.info);
    return fmt::format("no OpenCL device {} (--device N); the devices here:\n{}", index, device_list_text(infos));
  }
  auto impl = std::make_unique<Impl>();
  impl->info = devs[static_cast<std::size_t>(index)].info;
  impl->device = devs[static_cast<std::size_t>(index)].id;
  impl->precision = precision;
  const std::string dev = fmt::format("OpenCL device {}: {}", index, impl->info.describe());
  if (precision == Precision::float64 && !impl->info.fp64)
    return dev + ": has no double precision (cl_khr_fp64); run the kernel in float";
  cl_int e = 0;
  impl->context = clCreateContext(nullptr, 1, &impl->device, nullptr, nullptr, &e);
  if (e != CL_SUCCESS) return fmt::format("{}: clCreateContext failed ({})", dev, e);
  impl->queue = clCreateCommandQueue(impl->context, impl->device, 0, &e);
  if (e != CL_SUCCESS) return fmt::format("{}: clCreateCommandQueue failed ({})", dev, e);
  const char* src = source.c_str();
  const std::size_t len = source.size();
  impl->program = clCreateProgramWithSource(impl->context, 1, &src, &len, &e);
  if (e != CL_SUCCESS) return fmt::format("{}: clCreateProgramWithSource failed ({})", dev, e);
  e = clBuildProgram(impl->program, 1, &impl->device, options.c_str(), nullptr, nullptr);
  if (e != CL_SUCCESS) {
    std::size_t n = 0;
    clGetProgramBuildInfo(impl->program, impl->device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
    std::string log(n, '\0');
    if (n) clGetProgramBuildInfo(impl->program, impl->device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return fmt::format("{}: the build failed (error {}{}{}):\n{}", dev, e, options.empty() ? "" : ", options ",
                       options, log.empty() ? "(the build log is empty)" : log);
  }
  for (io::Kind k : kinds) {
    const std::string name = "rayproof_run_" + std::string(io::to_string(k));
    cl_kernel kern = clCreateKernel(impl->program, name.c_str(), &e);
    if (e != CL_SUCCESS) return fmt::format("{}: clCreateKernel {} failed ({})", dev, name, e);
    impl->kernels[k] = kern;
    std::size_t wg = 0;
    if (clGetKernelWorkGroupInfo(kern, impl->device, CL_KERNEL_WORK_GROUP_SIZE, sizeof wg, &wg, nullptr) == CL_SUCCESS &&
        wg > 0)
      impl->local = std::min(impl->local, wg);
  }
  if (auto err = impl->reserve(1024)) return dev + ": " + *err;
  for (io::Kind k : kinds)
    if (auto err = impl->launch(k, 0)) return dev + ": " + *err;
  return std::unique_ptr<Program>(new Program(std::move(impl)));
}

std::optional<std::string> Program::run(io::Kind kind, const void* in, std::size_t n, std::int32_t* codes, void* out) {
  Impl& m = *impl_;
  if (n == 0) return std::nullopt;
  if (auto err = m.reserve(n)) return err;
  const std::size_t rs = m.real_size(), nf = static_cast<std::size_t>(fields(kind));
  cl_int e = clEnqueueWriteBuffer(m.queue, m.in, CL_FALSE, 0, n * nf * rs, in, 0, nullptr, nullptr);
  if (e != CL_SUCCESS) return fmt::format("clEnqueueWriteBuffer failed ({})", e);
  if (auto err = m.launch(kind, n)) return err;
  static_assert(sizeof(cl_int) == sizeof(std::int32_t));
  e = clEnqueueReadBuffer(m.queue, m.code, CL_FALSE, 0, n * sizeof(cl_int), codes, 0, nullptr, nullptr);
  e |= clEnqueueReadBuffer(m.queue, m.out, CL_TRUE, 0, n * 3 * rs, out, 0, nullptr, nullptr);
  if (e != CL_SUCCESS) return fmt::format("clEnqueueReadBuffer failed ({})", e);
  return std::nullopt;
}

}  // namespace rayproof::opencl
