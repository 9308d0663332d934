// runGuarded (core/guarded_process.h): work in a child process under limits. Each way a parser
// can go wrong is played by a small piece of work: an endless loop (killed at the time limit), an
// allocation without end (killed at the memory limit or refused by RLIMIT_AS), a crash (the
// signal named), an exception (its message); the child's last stderr line comes with the problem;
// a large result (more than a pipe holds) comes back byte for byte; and the caller's own output
// is not touched by the child's. The limits are checked against the clock and /proc here.
#include "nestwalk/core/guarded_process.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

namespace nestwalk {
namespace {

double secondsOf(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(GuardedProcess, ResultComesBackByteForByte) {
  // 5 MB with every byte value: far more than a pipe buffers, so the caller must read while the
  // child writes.
  std::string big(5 << 20, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = char(i * 131 + (i >> 11));
  const GuardedResult r = runGuarded([&] { return big; });
  ASSERT_TRUE(r.ok) << r.problem;
  EXPECT_EQ(r.bytes, big);
  const GuardedResult empty = runGuarded([] { return std::string(); });
  ASSERT_TRUE(empty.ok) << empty.problem;
  EXPECT_TRUE(empty.bytes.empty());
}

TEST(GuardedProcess, EndlessLoopIsKilledAtTheTimeLimit) {
  ProcessLimits limits;
  limits.seconds = 0.5;
  GuardedResult r;
  const double took = secondsOf([&] {
    r = runGuarded(
        [] {
          volatile unsigned long spin = 0;
          for (;;) spin = spin + 1;
          return std::string();
        },
        limits);
  });
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.problem.rfind("took longer than 0.5 s", 0), 0u) << r.problem;
  EXPECT_GE(took, 0.5);
  EXPECT_LT(took, 2.0);
  // A child that sleeps (no CPU) is killed by the wall clock all the same.
  const GuardedResult sleeper = runGuarded(
      [] {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
        return std::string();
      },
      limits);
  EXPECT_EQ(sleeper.problem.rfind("took longer than 0.5 s", 0), 0u) << sleeper.problem;
}

TEST(GuardedProcess, AllocatingWithoutEndIsStoppedAtTheMemoryLimit) {
  ProcessLimits limits;
  limits.memoryBytes = 200ull << 20;
  limits.seconds = 20;
  GuardedResult r;
  const double took = secondsOf([&] {
    r = runGuarded(
        [] {
          std::vector<std::vector<char>> hog;
          for (;;) hog.emplace_back(16 << 20, 'x');  // touched: resident
          return std::string();
        },
        limits);
  });
  EXPECT_FALSE(r.ok);
  // Killed by the resident check, or refused by RLIMIT_AS first (bad_alloc in the child).
  const bool killed = r.problem.rfind("used more than 200 MiB of memory", 0) == 0;
  const bool refused = r.problem.rfind("ran out of memory", 0) == 0;
  EXPECT_TRUE(killed || refused) << r.problem;
  EXPECT_LT(took, 10.0);
  // The child's peak, from its rusage: about the limit (one more 16 MB block at most) when
  // killed, below the address-space limit when refused.
  EXPECT_GT(r.peakResidentBytes, 100ull << 20);
  EXPECT_LT(r.peakResidentBytes, limits.memoryBytes + kAddressSpaceSlack);
  EXPECT_NEAR(r.seconds, took, 0.05);
}

TEST(GuardedProcess, CrashIsNamed) {
  const GuardedResult r = runGuarded([]() -> std::string {
    std::fprintf(stderr, "about to fail\nreading block 7: bad checksum\n");
    std::fflush(stderr);
    // The default action, whoever handles SIGSEGV in this process (AddressSanitizer does: it
    // would report and exit instead of dying by the signal).
    std::signal(SIGSEGV, SIG_DFL);
    std::raise(SIGSEGV);
    return "unreachable";
  });
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.problem.rfind("crashed (signal " + std::to_string(SIGSEGV), 0), 0u) << r.problem;
  EXPECT_NE(r.problem.find("; it said: reading block 7: bad checksum"), std::string::npos) << r.problem;
  const GuardedResult aborted = runGuarded([]() -> std::string { std::abort(); });
  EXPECT_EQ(aborted.problem.rfind("crashed (signal " + std::to_string(SIGABRT), 0), 0u) << aborted.problem;
}

TEST(GuardedProcess, ExceptionBecomesTheProblem) {
  const GuardedResult r = runGuarded([]() -> std::string { throw std::runtime_error("unexpected end of file"); });
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.problem, "unexpected end of file");
}

TEST(GuardedProcess, ChildOutputDoesNotReachTheCallersStreams) {
  // The child's stdout and stderr go to the captured pipe: the caller's stdout (here a file)
  // receives nothing from it.
  std::FILE* capture = std::tmpfile();
  ASSERT_NE(capture, nullptr);
  std::fflush(stdout);
  const int saved = dup(fileno(stdout));
  dup2(fileno(capture), fileno(stdout));
  const GuardedResult r = runGuarded([] {
    std::printf("chatter on stdout\n");
    std::fflush(stdout);
    return std::string("ok");
  });
  std::fflush(stdout);
  dup2(saved, fileno(stdout));
  close(saved);
  std::fseek(capture, 0, SEEK_END);
  EXPECT_EQ(std::ftell(capture), 0L);
  std::fclose(capture);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.bytes, "ok");
}

TEST(GuardedProcess, LimitsFromTheEnvironment) {
  setenv("NESTWALK_MODEL_SECONDS", "3.5", 1);
  setenv("NESTWALK_MODEL_MEMORY_MB", "512", 1);
  ProcessLimits l = modelReadLimitsFromEnvironment();
  EXPECT_EQ(l.seconds, 3.5);
  EXPECT_EQ(l.memoryBytes, 512ull << 20);
  setenv("NESTWALK_MODEL_SECONDS", "soon", 1);
  setenv("NESTWALK_MODEL_MEMORY_MB", "-4", 1);
  l = modelReadLimitsFromEnvironment();
  EXPECT_EQ(l.seconds, ProcessLimits{}.seconds);
  EXPECT_EQ(l.memoryBytes, ProcessLimits{}.memoryBytes);
  unsetenv("NESTWALK_MODEL_SECONDS");
  unsetenv("NESTWALK_MODEL_MEMORY_MB");
}

}  // namespace
}  // namespace nestwalk
