// The background builder the paged terrain's chunks and the imagery's tiles share: worker threads
// that take keys from a queue the drawing thread replaces each frame, build each with the given
// function and leave the result for the drawing thread to take (paged_terrain.h, imagery_tiles.h).
//
// Workers: the first runs at the process's priority; the others (helpers) run kHelperNiceIncrement
// lower (Linux's per-thread nice value), so that they take the cores the drawing thread and the
// first worker leave idle (the settling view waiting for its chunks) and yield them to a frame that
// is drawing. Each worker takes the queue's first key; a key's build may finish before an earlier
// one's, so results come in any order.
//
// Shared state (Shared): the queue (what to build next, first first), the keys being built and the
// built results not yet taken. Both sides reach it only through locked(), under one mutex; the
// builder never runs the build function under it. A key being built, or built and not taken, is
// skipped when it comes up again. A build that throws (out of memory) leaves nothing; the first such
// error is kept (error(), prefixed with the key's name) and the caller draws what stands in for it.
//
// Follow-ups (optional): after a build, the worker calls follow(result, shared) under the lock, before
// the result joins `done`; it may queue what the result shows will be wanted next (the paged
// terrain's children the last view needs, paged_terrain.h "Loading"), so that the workers go on
// without waiting for the drawing side to take the result and ask. It must be short: it holds the lock.
//
// Result must have a `key` member comparable with Key. The build function is called from every worker
// at once and must be safe so. Ownership: the builder owns its threads, which it starts on
// construction and stops and joins on destruction (after the builds in progress); whatever the build
// function reads must outlive the builder.
#pragma once

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace nestwalk {

/// Helper workers' nice value above the process's: CFS then gives a busy drawing thread about ten
/// times their share of a core (weights 1024 against 110), and them all of an idle one.
inline constexpr int kHelperNiceIncrement = 10;

/// Workers for a builder on this machine: one per hardware thread, at least 1, at most `most`.
inline int builderWorkers(int most) {
  return std::clamp(int(std::thread::hardware_concurrency()), 1, std::max(1, most));
}

template <class Key, class Result>
class BuildQueue {
 public:
  struct Shared {
    std::vector<Key> queue;     // to build, first first (the drawing side replaces it)
    std::vector<Key> inFlight;  // being built
    std::vector<Result> done;   // built, waiting to be taken
    /// Being built, or built and waiting.
    bool known(const Key& key) const {
      return std::find(inFlight.begin(), inFlight.end(), key) != inFlight.end() ||
             std::any_of(done.begin(), done.end(), [&](const Result& r) { return r.key == key; });
    }
  };

  using Follow = std::function<void(const Result&, Shared&)>;

  /// `workers` threads (at least 1), the first at the process's priority, the rest as helpers;
  /// `follow` (may be empty) as above.
  BuildQueue(std::function<Result(const Key&)> build, std::function<std::string(const Key&)> name, int workers = 1,
             Follow follow = {})
      : build_(std::move(build)), name_(std::move(name)), follow_(std::move(follow)) {
    try {
      for (int w = 0; w < std::max(1, workers); ++w) threads_.emplace_back([this, w] { loop(w > 0); });
    } catch (...) {
      stop();  // a thread that could not start: the ones that did are joined before the throw
      throw;
    }
  }
  ~BuildQueue() { stop(); }
  BuildQueue(const BuildQueue&) = delete;
  BuildQueue& operator=(const BuildQueue&) = delete;

  /// Runs f(Shared&) under the lock and wakes the workers (a queue it changed is picked up).
  template <class F>
  decltype(auto) locked(F&& f) {
    struct Wake {
      std::condition_variable& cv;
      ~Wake() { cv.notify_all(); }
    } wake{wake_};
    std::lock_guard lock(mutex_);
    return f(shared_);
  }

  /// Waits until the queue is empty and nothing is being built.
  void waitUntilIdle() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return stop_ || (shared_.queue.empty() && shared_.inFlight.empty()); });
  }

  /// The first build that failed, "NAME: what" (empty: none).
  std::string error() const {
    std::lock_guard lock(mutex_);
    return error_;
  }

 private:
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  void loop(bool helper) {
    // A failure leaves the helper at the process's priority: slower to settle where cores are
    // short, never wrong.
    if (helper)
      (void)::setpriority(PRIO_PROCESS, id_t(::syscall(SYS_gettid)), ::getpriority(PRIO_PROCESS, 0) + kHelperNiceIncrement);
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || !shared_.queue.empty(); });
      if (stop_) return;
      const Key key = shared_.queue.front();
      shared_.queue.erase(shared_.queue.begin());
      if (!shared_.known(key)) {
        shared_.inFlight.push_back(key);
        lock.unlock();
        std::optional<Result> result;
        std::string failure;
        try {
          result.emplace(build_(key));
        } catch (const std::exception& e) {
          failure = e.what();
        }
        lock.lock();
        shared_.inFlight.erase(std::find(shared_.inFlight.begin(), shared_.inFlight.end(), key));
        if (result && follow_) {
          const std::size_t queued = shared_.queue.size();
          follow_(*result, shared_);
          if (shared_.queue.size() > queued) wake_.notify_all();
        }
        if (result) shared_.done.push_back(std::move(*result));
        else if (error_.empty()) error_ = name_(key) + ": " + failure;
      }
      if (shared_.queue.empty() && shared_.inFlight.empty()) idle_.notify_all();
    }
  }

  std::function<Result(const Key&)> build_;
  std::function<std::string(const Key&)> name_;
  Follow follow_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  Shared shared_;
  bool stop_ = false;
  std::string error_;
  std::vector<std::thread> threads_;  // last: started once everything above exists
};

}  // namespace nestwalk
