// The background builder the paged terrain's chunks and the imagery's tiles share: one thread that
// takes keys from a queue the drawing thread replaces each frame, builds each with the given
// function and leaves the result for the drawing thread to take (paged_terrain.h, imagery_tiles.h).
//
// Shared state (Shared): the queue (what to build next, first first), the keys being built and the
// built results not yet taken. Both sides reach it only through locked(), under one mutex; the
// builder never runs the build function under it. A key being built, or built and not taken, is
// skipped when it comes up again. A build that throws (out of memory) leaves nothing; the first such
// error is kept (error(), prefixed with the key's name) and the caller draws what stands in for it.
//
// Result must have a `key` member comparable with Key. Ownership: the builder owns its thread,
// which it starts on construction and stops and joins on destruction (after the build in progress);
// whatever the build function reads must outlive the builder.
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

namespace nestwalk {

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

  BuildQueue(std::function<Result(const Key&)> build, std::function<std::string(const Key&)> name)
      : build_(std::move(build)), name_(std::move(name)), thread_([this] { loop(); }) {}
  ~BuildQueue() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  BuildQueue(const BuildQueue&) = delete;
  BuildQueue& operator=(const BuildQueue&) = delete;

  /// Runs f(Shared&) under the lock and wakes the builder (a queue it changed is picked up).
  template <class F>
  decltype(auto) locked(F&& f) {
    struct Wake {
      std::condition_variable& cv;
      ~Wake() { cv.notify_one(); }
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
  void loop() {
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
        if (result) shared_.done.push_back(std::move(*result));
        else if (error_.empty()) error_ = name_(key) + ": " + failure;
      }
      if (shared_.queue.empty() && shared_.inFlight.empty()) idle_.notify_all();
    }
  }

  std::function<Result(const Key&)> build_;
  std::function<std::string(const Key&)> name_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  Shared shared_;
  bool stop_ = false;
  std::string error_;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace nestwalk
