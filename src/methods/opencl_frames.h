#pragma once
/// The private framing between rayproof and its OpenCL device process (`rayproof opencl-host`,
/// both the same executable): a 16-byte header (tag, payload bytes) and the payload, over pipes.
/// R: ready (text: the device's description lines). E: an error message (text); the process then
/// exits. B: a batch (int32 kind, then fields(kind) doubles per case). A: the answers (per case
/// int32 code, int32 0, double t, b1, b2).
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

struct WireAnswer {
  std::int32_t code = -1;
  std::int32_t zero = 0;
  double t = 0, b1 = 0, b2 = 0;
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
