#include "methods/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

extern char** environ;

namespace rayproof::proc {

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

std::string spawn(const std::string& path, const std::vector<std::string>& argv, const SpawnOptions& opt, Child& out) {
  out = Child{};
  int pin[2], pout[2], perr[2] = {-1, -1};
  if (::pipe2(pin, O_CLOEXEC) != 0) return std::string("pipe: ") + std::strerror(errno);
  if (::pipe2(pout, O_CLOEXEC) != 0) {
    ::close(pin[0]), ::close(pin[1]);
    return std::string("pipe: ") + std::strerror(errno);
  }
  if (opt.pipe_stderr && ::pipe2(perr, O_CLOEXEC) != 0) {
    ::close(pin[0]), ::close(pin[1]), ::close(pout[0]), ::close(pout[1]);
    return std::string("pipe: ") + std::strerror(errno);
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, pin[0], 0);
  posix_spawn_file_actions_adddup2(&fa, pout[1], 1);
  if (opt.pipe_stderr) posix_spawn_file_actions_adddup2(&fa, perr[1], 2);
  if (opt.fd3 >= 0) posix_spawn_file_actions_adddup2(&fa, opt.fd3, 3);
  posix_spawnattr_t at;
  posix_spawnattr_init(&at);
  sigset_t def, none;
  sigemptyset(&def);
  sigaddset(&def, SIGPIPE);  // the parent ignores SIGPIPE; the child gets the default back
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&at, &def);
  posix_spawnattr_setsigmask(&at, &none);
  short flags = POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK;
  if (opt.own_process_group) {
    posix_spawnattr_setpgroup(&at, 0);
    flags |= POSIX_SPAWN_SETPGROUP;
  }
  posix_spawnattr_setflags(&at, flags);
  std::vector<std::string> args = argv;
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, path.c_str(), &fa, &at, cargs.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  ::close(pin[0]), ::close(pout[1]);
  if (opt.pipe_stderr) ::close(perr[1]);
  if (rc != 0) {
    ::close(pin[1]), ::close(pout[0]);
    if (opt.pipe_stderr) ::close(perr[0]);
    return std::string("cannot start ") + path + ": " + std::strerror(rc);
  }
  out = Child{pid, pin[1], pout[0], perr[0]};
  return "";
}

std::string status_text(int status) {
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    return "killed by signal " + std::to_string(sig) + (name ? std::string(" (") + name + ")" : std::string());
  }
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  return "ended";
}

std::string end(Child& ch, bool kill_first, bool group) {
  close_fd(ch.to);
  if (ch.pid <= 0) {
    close_fd(ch.from), close_fd(ch.err);
    return "not running";
  }
  if (kill_first) {
    if (group) ::kill(-ch.pid, SIGKILL);
    ::kill(ch.pid, SIGKILL);
  }
  int status = 0;
  while (::waitpid(ch.pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (group) ::kill(-ch.pid, SIGKILL);  // anything it started and left behind
  close_fd(ch.from), close_fd(ch.err);
  ch.pid = -1;
  return status_text(status);
}

namespace {

template <short Event, class Op>
Io transfer(int fd, std::size_t n, Clock::time_point deadline, Op op) {
  while (n > 0) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) return Io::timeout;
    pollfd pf{fd, Event, 0};
    const int pr = ::poll(&pf, 1, static_cast<int>(std::ceil(std::min(left, 1e6) * 1000)));
    if (pr < 0 && errno == EINTR) continue;
    if (pr < 0) return Io::error;
    if (pr == 0) return Io::timeout;
    const ssize_t r = op(n);
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (r <= 0) return Io::eof;
    n -= static_cast<std::size_t>(r);
  }
  return Io::ok;
}

}  // namespace

Io write_all(int fd, const void* data, std::size_t n, Clock::time_point deadline) {
  const char* p = static_cast<const char*>(data);
  const std::size_t total = n;
  return transfer<POLLOUT>(fd, n, deadline, [&](std::size_t left) {
    const ssize_t w = ::write(fd, p + (total - left), left);
    return w;
  });
}

Io read_all(int fd, void* data, std::size_t n, Clock::time_point deadline) {
  char* p = static_cast<char*>(data);
  const std::size_t total = n;
  return transfer<POLLIN>(fd, n, deadline, [&](std::size_t left) { return ::read(fd, p + (total - left), left); });
}

}  // namespace rayproof::proc
