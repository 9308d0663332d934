// A child process under time and memory limits (guarded_process.h).
#include "nestwalk/core/guarded_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define NESTWALK_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define NESTWALK_SANITIZED 1
#endif
#endif

namespace nestwalk {
namespace {

/// Bytes of the child's stderr kept (its last line is what matters).
constexpr std::size_t kStderrTail = 4096;
/// Characters of that last line quoted in a problem.
constexpr std::size_t kQuotedLine = 200;

constexpr char kResultOk = 'O', kResultError = 'E';

/// Writes all of `data` to `fd` (the child's side); false on failure.
bool writeAll(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    size -= std::size_t(n);
  }
  return true;
}

[[noreturn]] void runChild(const std::function<std::string()>& work, const ProcessLimits& limits, int resultFd,
                           int stderrFd) {
  ::dup2(stderrFd, STDERR_FILENO);
  ::dup2(stderrFd, STDOUT_FILENO);  // a parser's chatter must not mix with the caller's output
  ::close(stderrFd);
  rlimit cpu{};
  cpu.rlim_cur = rlim_t(std::ceil(limits.seconds));
  cpu.rlim_max = cpu.rlim_cur + 1;
  ::setrlimit(RLIMIT_CPU, &cpu);
#ifndef NESTWALK_SANITIZED
  rlimit as{};
  as.rlim_cur = as.rlim_max = rlim_t(limits.memoryBytes + kAddressSpaceSlack);
  ::setrlimit(RLIMIT_AS, &as);
#endif
  std::string out;
  char status = kResultOk;
  try {
    out = work();
  } catch (const std::bad_alloc&) {
    status = kResultError;
    out = "ran out of memory";
  } catch (const std::exception& e) {
    status = kResultError;
    out = e.what();
  } catch (...) {
    status = kResultError;
    out = "failed";
  }
  const bool written = writeAll(resultFd, &status, 1) && writeAll(resultFd, out.data(), out.size());
  ::_exit(written ? 0 : 1);
}

/// The child's resident memory in bytes (0 when /proc cannot tell).
std::uint64_t residentBytes(pid_t pid) {
  std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
  std::uint64_t size = 0, resident = 0;
  if (!(statm >> size >> resident)) return 0;
  return resident * std::uint64_t(::sysconf(_SC_PAGESIZE));
}

/// The last non-empty line of `text`, trimmed and shortened.
std::string lastLine(const std::string& text) {
  std::size_t end = text.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) return "";
  const std::size_t start = text.find_last_of("\r\n", end);
  std::string line = text.substr(start == std::string::npos ? 0 : start + 1, end + 1 - (start == std::string::npos ? 0 : start + 1));
  const std::size_t first = line.find_first_not_of(" \t");
  line = first == std::string::npos ? "" : line.substr(first);
  if (line.size() > kQuotedLine) line = line.substr(0, kQuotedLine) + "...";
  return line;
}

std::string secondsText(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

}  // namespace

GuardedResult runGuarded(const std::function<std::string()>& work, const ProcessLimits& limits) {
  int resultPipe[2], stderrPipe[2];
  if (::pipe2(resultPipe, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  if (::pipe2(stderrPipe, O_CLOEXEC) != 0) {
    ::close(resultPipe[0]);
    ::close(resultPipe[1]);
    throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  }
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (int fd : {resultPipe[0], resultPipe[1], stderrPipe[0], stderrPipe[1]}) ::close(fd);
    throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(resultPipe[0]);
    ::close(stderrPipe[0]);
    runChild(work, limits, resultPipe[1], stderrPipe[1]);
  }
  ::close(resultPipe[1]);
  ::close(stderrPipe[1]);
  const auto start = std::chrono::steady_clock::now();
  std::string result, errors;
  pollfd fds[2] = {{resultPipe[0], POLLIN, 0}, {stderrPipe[0], POLLIN, 0}};
  bool open[2] = {true, true};
  std::string killedFor;
  char buffer[65536];
  while (open[0] || open[1]) {
    const int ready = ::poll(fds, 2, int(kPollInterval.count()));
    if (ready < 0 && errno != EINTR) break;
    for (int k = 0; k < 2; ++k) {
      if (!open[k] || !(fds[k].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(fds[k].fd, buffer, sizeof buffer);
      if (n > 0) {
        if (k == 0) {
          result.append(buffer, std::size_t(n));
        } else {
          errors.append(buffer, std::size_t(n));
          if (errors.size() > 2 * kStderrTail) errors.erase(0, errors.size() - kStderrTail);
        }
      } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
        open[k] = false;
        fds[k].fd = -1;  // poll ignores it from now on
      }
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > limits.seconds) {
      killedFor = "took longer than " + secondsText(limits.seconds) + " s";
    } else if (residentBytes(pid) > limits.memoryBytes) {
      killedFor = "used more than " + std::to_string(limits.memoryBytes >> 20) + " MiB of memory";
    }
    if (!killedFor.empty()) {
      ::kill(pid, SIGKILL);
      break;
    }
  }
  ::close(resultPipe[0]);
  ::close(stderrPipe[0]);
  int status = 0;
  rusage usage{};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }

  GuardedResult out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.peakResidentBytes = std::uint64_t(usage.ru_maxrss) * 1024;  // kilobytes on Linux
  if (killedFor.empty() && WIFEXITED(status) && WEXITSTATUS(status) == 0 && !result.empty()) {
    out.ok = result[0] == kResultOk;
    if (out.ok) out.bytes = result.substr(1);
    else out.problem = result.substr(1);
  } else if (!killedFor.empty()) {
    out.problem = killedFor;
  } else if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    out.problem = sig == SIGXCPU ? "used more than " + secondsText(limits.seconds) + " s of CPU time"
                                 : "crashed (signal " + std::to_string(sig) + ", " + ::strsignal(sig) + ")";
  } else {
    out.problem = "ended without a result (exit code " + std::to_string(WEXITSTATUS(status)) + ")";
  }
  if (!out.ok) {
    const std::string said = lastLine(errors);
    if (!said.empty()) out.problem += "; it said: " + said;
  }
  return out;
}

ProcessLimits modelReadLimitsFromEnvironment() {
  ProcessLimits limits;
  auto positive = [](const char* name) {
    const char* text = std::getenv(name);
    if (!text) return 0.0;
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    return end != text && *end == '\0' && std::isfinite(v) && v > 0 ? v : 0.0;
  };
  if (const double s = positive("NESTWALK_MODEL_SECONDS"); s > 0) limits.seconds = s;
  if (const double mb = positive("NESTWALK_MODEL_MEMORY_MB"); mb > 0) limits.memoryBytes = std::uint64_t(mb * (1 << 20));
  return limits;
}

}  // namespace nestwalk
