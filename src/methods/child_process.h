#pragma once
/// The processes that run users' kernels (--exec commands, the --opencl and --glsl device hosts):
/// starting one with its standard input and output as pipes, reading and writing them before a
/// deadline, ending it and saying how it ended. One helper for the three kinds of kernel, so that
/// each starts its child with the same signal state and the same descriptors.
#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

namespace rayproof::proc {

using Clock = std::chrono::steady_clock;

/// The parent's ends of a child's pipes (-1: none).
struct Child {
  pid_t pid = -1;
  int to = -1;    ///< the child's standard input
  int from = -1;  ///< the child's standard output
  int err = -1;   ///< the child's standard error, when SpawnOptions::pipe_stderr
};

struct SpawnOptions {
  bool own_process_group = false;  ///< the child leads a new process group (kill(-pid) ends all it started)
  bool pipe_stderr = false;        ///< standard error as a pipe too (else the child shares ours)
  int fd3 = -1;                    ///< when >= 0, passed to the child as its descriptor 3
};

/// Starts `path` with `argv` (argv[0] first): its standard input and output are pipes whose other
/// ends land in `out`; in the child SIGPIPE has its default action and no signal is blocked, and
/// the parent's descriptors (opened close-on-exec) are not inherited. "" on success, else why not
/// (out is left empty then).
[[nodiscard]] std::string spawn(const std::string& path, const std::vector<std::string>& argv, const SpawnOptions& opt,
                                Child& out);

/// Closes fd when open and sets it to -1.
void close_fd(int& fd);

/// Closes the pipes, kills the child first when `kill_first` (its group too when it leads one),
/// waits for it: how it ended ("exited with status 3", "killed by signal 11 (Segmentation fault)"),
/// or "not running".
std::string end(Child& ch, bool kill_first, bool group = false);

/// A wait status in words: "exited with status 3", "killed by signal 11 (Segmentation fault)".
[[nodiscard]] std::string status_text(int status);

enum class Io { ok, eof, timeout, error };

/// Writes or reads all n bytes before the deadline (poll, then write or read; EINTR and EAGAIN retried).
[[nodiscard]] Io write_all(int fd, const void* data, std::size_t n, Clock::time_point deadline);
[[nodiscard]] Io read_all(int fd, void* data, std::size_t n, Clock::time_point deadline);

}  // namespace rayproof::proc
