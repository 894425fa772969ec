#pragma once
// Fork-join over a fixed list of tasks. Kernels cut their work into tasks
// whose boundaries do not depend on the number of threads, so results are
// bit-identical whatever executor runs them (serial included).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace pleat::nn {

using TaskFn = void (*)(void* context, int32_t task);

class Executor {
 public:
  virtual ~Executor() = default;
  // Calls fn(context, t) once for every t in [0, tasks) and returns when all
  // have returned. Tasks may run concurrently and in any order; fn must not
  // throw. One run() at a time per executor.
  virtual void run(int32_t tasks, TaskFn fn, void* context) = 0;
  virtual int32_t concurrency() const = 0;
};

// Runs every task on the calling thread, in order.
class SerialExecutor final : public Executor {
 public:
  void run(int32_t tasks, TaskFn fn, void* context) override {
    for (int32_t t = 0; t < tasks; ++t) fn(context, t);
  }
  int32_t concurrency() const override { return 1; }
};

// threads - 1 persistent workers plus the calling thread. Allocates only in
// the constructor. An idle worker, and the calling thread waiting for the
// last task, spin (yielding) for up to kSpin before sleeping on a condition
// variable: a frame runs some twenty phases a few hundred microseconds
// apart, and a futex wake-up on these virtual machines costs as much as a
// phase (2 threads, 4,096 vertices: 5.9 -> 3.7 ms/frame from 50 to 500 us,
// docs/benchmarks.md). When kernels run on it, pin OpenBLAS to one thread
// (spectral/blas_threads.h: SingleThreadedBlas) so the two pools do not
// fight over the cores.
class ThreadPool final : public Executor {
 public:
  explicit ThreadPool(int32_t threads);
  ~ThreadPool() override;
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  void run(int32_t tasks, TaskFn fn, void* context) override;
  int32_t concurrency() const override { return static_cast<int32_t>(workers_.size()) + 1; }
  static constexpr auto kSpin = std::chrono::microseconds(500);

 private:
  void work();
  void drain();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  std::atomic<uint64_t> generation_{0};  // written under mutex_, spun on without it
  std::atomic<int32_t> busy_{0};         // workers inside drain(); written under mutex_
  bool stop_ = false;
  TaskFn fn_ = nullptr;
  void* context_ = nullptr;
  int32_t tasks_ = 0;
  std::atomic<int32_t> next_{0};
  std::atomic<int32_t> finished_{0};
};

}  // namespace pleat::nn
