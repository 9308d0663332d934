// The background builder (engine/render/build_queue.h) with several workers: every key asked for is
// built once and handed over; the workers build at once; the helpers run at a lower priority (their
// nice value, read from the kernel in the build itself), the first worker at the process's.
#include "nestwalk/render/build_queue.h"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace nestwalk {
namespace {

struct Built {
  int key = 0;
  long thread = 0;
  int nice = 0;
};

TEST(BuildQueue, SeveralWorkersBuildEachKeyOnceAndTheHelpersRunAtALowerPriority) {
  constexpr int kWorkers = 3, kKeys = 60;
  std::atomic<int> running{0}, mostAtOnce{0};
  std::mutex calls;
  std::map<int, int> builtTimes;
  BuildQueue<int, Built> queue(
      [&](const int& key) {
        const int now = ++running;
        int seen = mostAtOnce.load();
        while (now > seen && !mostAtOnce.compare_exchange_weak(seen, now)) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));  // long enough for the others to start one
        {
          const std::lock_guard lock(calls);
          ++builtTimes[key];
        }
        --running;
        const long tid = ::syscall(SYS_gettid);
        return Built{key, tid, ::getpriority(PRIO_PROCESS, id_t(tid))};
      },
      [](const int& key) { return "key " + std::to_string(key); }, kWorkers);
  // Each key asked for twice: the second is skipped while it is being built or waiting.
  queue.locked([&](auto& shared) {
    for (int k = 0; k < kKeys; ++k) shared.queue.push_back(k);
    for (int k = 0; k < kKeys; ++k) shared.queue.push_back(k);
  });
  queue.waitUntilIdle();
  std::vector<Built> done;
  queue.locked([&](auto& shared) { done = std::move(shared.done); });
  EXPECT_EQ(queue.error(), "");

  std::set<int> keys;
  for (const Built& b : done) keys.insert(b.key);
  EXPECT_EQ(keys.size(), std::size_t(kKeys));
  EXPECT_EQ(done.size(), std::size_t(kKeys));  // none twice
  for (const auto& [key, times] : builtTimes) EXPECT_EQ(times, 1) << "key " << key;
  EXPECT_GE(mostAtOnce.load(), 2);  // the workers overlap (2 ms builds, 3 workers)

  // The nice values: the process's for one worker, kHelperNiceIncrement more (capped at 19) for the others.
  const int base = ::getpriority(PRIO_PROCESS, 0), helper = std::min(19, base + kHelperNiceIncrement);
  std::map<long, int> niceOf;
  for (const Built& b : done) niceOf[b.thread] = b.nice;
  ASSERT_GE(niceOf.size(), 2u);
  ASSERT_LE(niceOf.size(), std::size_t(kWorkers));
  std::size_t atBase = 0, atHelper = 0;
  for (const auto& [thread, nice] : niceOf) {
    atBase += nice == base;
    atHelper += nice == helper;
  }
  EXPECT_LE(atBase, 1u);
  EXPECT_EQ(atBase + atHelper, niceOf.size());
  if (base < 19) {
    EXPECT_GE(atHelper, 1u);
  }
}

TEST(BuildQueue, AFollowUpQueuesWhatAResultShowsIsNextAndIdleWaitsForIt) {
  // Key k's follow-up queues k + 1 up to 20: one key asked for, the chain built without the caller.
  constexpr int kLast = 20;
  std::mutex calls;
  std::map<int, int> builtTimes;
  BuildQueue<int, Built> queue(
      [&](const int& key) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        const std::lock_guard lock(calls);
        ++builtTimes[key];
        return Built{key, 0, 0};
      },
      [](const int& key) { return "key " + std::to_string(key); }, 2,
      [](const Built& built, BuildQueue<int, Built>::Shared& shared) {
        // Under the lock: the built key is neither queued nor in flight any more, and not done yet.
        EXPECT_FALSE(shared.known(built.key));
        if (built.key < kLast) shared.queue.push_back(built.key + 1);
      });
  queue.locked([](auto& shared) { shared.queue.push_back(0); });
  queue.waitUntilIdle();  // returns only once the last follow-up is built
  std::vector<Built> done;
  queue.locked([&](auto& shared) { done = std::move(shared.done); });
  ASSERT_EQ(done.size(), std::size_t(kLast + 1));
  for (int k = 0; k <= kLast; ++k) {
    EXPECT_EQ(done[std::size_t(k)].key, k);  // each queued by the one before, after it was built
    EXPECT_EQ(builtTimes[k], 1) << "key " << k;
  }
}

TEST(BuildQueue, BuilderWorkersFollowTheMachineWithinTheirBounds) {
  const int cores = std::max(1, int(std::thread::hardware_concurrency()));
  EXPECT_EQ(builderWorkers(64), std::min(cores, 64));
  EXPECT_EQ(builderWorkers(1), 1);
  EXPECT_EQ(builderWorkers(0), 1);
}

}  // namespace
}  // namespace nestwalk
