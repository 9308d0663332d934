// Running untrusted parsing where it cannot hurt: a piece of work runs in a child process (fork)
// under a wall-clock limit and a memory limit, and hands its result back as bytes through a pipe.
// A parser that loops, allocates without end or crashes on a corrupt file takes only the child
// down; the caller gets a problem to report, within the time limit, with the memory bounded.
//
// Why a process and not a thread: a thread cannot be stopped from outside, and its memory and
// crashes are the caller's. The child is a copy of the caller at the moment of the call (fork),
// so the work may use anything the caller has loaded; nothing it does reaches back.
//
// Limits, enforced by the caller while it reads the child's output:
//  - time: the child is killed (SIGKILL) once `seconds` of wall-clock time have passed; it also
//    runs under RLIMIT_CPU of the same length, so a CPU-bound loop ends even if the caller stops
//    watching;
//  - memory: the child's resident memory is read from /proc every kPollInterval and it is killed
//    above `memoryBytes`; outside AddressSanitizer builds it also runs under RLIMIT_AS of
//    memoryBytes plus kAddressSpaceSlack (ASan reserves terabytes of address space up front, so
//    the resident check alone bounds it there).
// The child's stderr is captured; its last line (a parser's own complaint) comes with a problem.
// The child ends with _exit: no atexit handlers, no flushing of the caller's buffered output.
//
// Thread safety: call from one thread at a time per process, and not while other threads hold
// locks the work needs (fork copies only the calling thread; the locks others held stay locked
// in the child). nestwalk reads models while loading a scene, before any worker thread starts.
// The child inherits the caller's open file descriptors (fork without exec, so O_CLOEXEC does not
// help): two calls at once from different threads could each hand their child the other's pipe
// ends, and one call would then wait for the other's child (or its own time limit) before it sees
// the end of its output. modelReadLimitsFromEnvironment reads the environment (getenv): not while
// another thread changes it.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace nestwalk {

struct ProcessLimits {
  double seconds = 10.0;                       // wall clock, and CPU time, of the child
  std::uint64_t memoryBytes = 2ull << 30;      // resident memory of the child (2 GiB)
};

/// How often the caller checks the child's time and memory while it waits.
inline constexpr std::chrono::milliseconds kPollInterval{10};
/// Address space allowed beyond memoryBytes (RLIMIT_AS counts mapped libraries, thread stacks and
/// allocator reserves that are never resident): 512 MiB.
inline constexpr std::uint64_t kAddressSpaceSlack = 512ull << 20;

struct GuardedResult {
  bool ok = false;
  std::string bytes;    // what the work returned (ok)
  std::string problem;  // why not (not ok): "took longer than 10 s", "used more than 2048 MiB of
                        // memory", "crashed (signal 11, Segmentation fault)", the work's own
                        // exception message; with "; it said: <last line of its stderr>" when
                        // it printed one
  double seconds = 0;                // wall-clock time from the start to the child's end
  std::uint64_t peakResidentBytes = 0;  // the child's largest resident memory (its rusage)
};

/// Runs `work` in a child process under `limits` and returns its bytes, or the problem. An
/// exception thrown by the work becomes the problem (its what()). Failing to start the child
/// (fork, pipe) throws std::runtime_error.
GuardedResult runGuarded(const std::function<std::string()>& work, const ProcessLimits& limits = {});

/// The limits from the environment: NESTWALK_MODEL_SECONDS and NESTWALK_MODEL_MEMORY_MB override
/// the defaults above (a value that is not a positive number is ignored).
ProcessLimits modelReadLimitsFromEnvironment();

}  // namespace nestwalk
