#pragma once
/// The private framing between rayproof and its OpenCL device process (`rayproof opencl-host`,
/// both the same executable): a 16-byte header (tag, payload bytes) and the payload, over pipes.
/// R: ready (text: the device's description lines). E: an error message (text); the process then
/// exits. B: a batch (BatchFrame); its cases are in the shared memory (ShmLayout), as the kernel's
/// reals (float or double), fields(kind) per case. A: the answers are in the shared memory (the
/// payload repeats the case count).
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>

namespace rayproof::opencl {

struct FrameHeader {
  std::uint32_t tag = 0;
  std::uint32_t zero = 0;
  std::uint64_t bytes = 0;
};

struct BatchFrame {
  std::int32_t kind = 0;
  std::uint32_t cases = 0;
};

/// The shared memory of one device process (a memfd, fd 3 in the child): the inputs (15 reals a
/// case, whatever the kind), the return codes (int32), the answers (t, b1, b2 a case).
struct ShmLayout {
  std::size_t max_cases = 0, real_size = 4;
  [[nodiscard]] std::size_t in_offset() const { return 0; }
  [[nodiscard]] std::size_t code_offset() const { return max_cases * 15 * real_size; }
  [[nodiscard]] std::size_t out_offset() const { return code_offset() + max_cases * 4; }
  [[nodiscard]] std::size_t bytes() const { return out_offset() + max_cases * 3 * real_size; }
};

/// Writes all of `n` bytes; false on an error (EPIPE: the other side is gone).
inline bool write_all(int fd, const void* p, std::size_t n) {
  const char* c = static_cast<const char*>(p);
  while (n > 0) {
    const ssize_t w = ::write(fd, c, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    c += w, n -= static_cast<std::size_t>(w);
  }
  return true;
}

/// Reads exactly `n` bytes (blocking); false at end of input or on an error.
inline bool read_all(int fd, void* p, std::size_t n) {
  char* c = static_cast<char*>(p);
  while (n > 0) {
    const ssize_t r = ::read(fd, c, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    c += r, n -= static_cast<std::size_t>(r);
  }
  return true;
}

inline bool write_frame(int fd, char tag, const void* payload, std::size_t n) {
  FrameHeader h{static_cast<std::uint32_t>(tag), 0, n};
  return write_all(fd, &h, sizeof h) && (n == 0 || write_all(fd, payload, n));
}

inline bool write_text_frame(int fd, char tag, const std::string& s) { return write_frame(fd, tag, s.data(), s.size()); }

}  // namespace rayproof::opencl
