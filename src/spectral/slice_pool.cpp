#include "spectral/slice_pool.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace pleat {
namespace {

constexpr int kMaxWorkers = 8;

std::string slice_label(size_t index) {
  return "slice " + std::to_string(index);
}

// Slices placed but not yet taken by a worker; results land at their index.
class SliceQueue {
 public:
  void push(const SliceBounds& bounds) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      placed_.push_back(bounds);
      results_.emplace_back();
    }
    ready_.notify_one();
  }
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }
  // Blocks until a slice is available; false once none will come.
  bool take(size_t* index, SliceBounds* bounds) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return failed_ || closed_ || next_ < placed_.size(); });
    if (failed_ || next_ >= placed_.size()) return false;
    *index = next_++;
    *bounds = placed_[*index];
    return true;
  }
  void store(size_t index, EigenPairs pairs) {
    std::lock_guard<std::mutex> lock(mutex_);
    results_[index] = std::move(pairs);
  }
  // Keeps the error of the lowest failing slice (the one a sequential run
  // would report) and stops everyone.
  void fail(size_t index, std::exception_ptr error) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_ || index < error_index_) {
        error_ = std::move(error);
        error_index_ = index;
      }
      failed_ = true;
    }
    ready_.notify_all();
  }
  bool failed() {
    std::lock_guard<std::mutex> lock(mutex_);
    return failed_;
  }
  SolvedSlices finish() {
    if (error_) std::rethrow_exception(error_);
    SolvedSlices solved;
    for (size_t i = 1; i < placed_.size(); ++i) solved.boundaries.push_back(placed_[i].lo.sigma);
    solved.slices = std::move(results_);
    return solved;
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::vector<SliceBounds> placed_;
  std::vector<EigenPairs> results_;
  size_t next_ = 0;
  bool closed_ = false;
  bool failed_ = false;
  std::exception_ptr error_;
  size_t error_index_ = 0;
};

void work(const Eigen::SparseMatrix<double>& laplacian, SliceQueue* queue) {
  size_t index = 0;
  SliceBounds bounds;
  try {
    Slicer slicer(laplacian);
    while (queue->take(&index, &bounds))
      queue->store(index, slicer.solve_interval(bounds.lo, bounds.hi, slice_label(index)));
  } catch (...) {
    queue->fail(index, std::current_exception());
  }
}

}  // namespace

int default_slice_workers() {
  const unsigned hardware = std::thread::hardware_concurrency();
  return std::clamp(static_cast<int>(hardware), 1, kMaxWorkers);
}

SolvedSlices solve_slices(const Eigen::SparseMatrix<double>& laplacian, SlicePlanner* planner, int workers) {
  SliceQueue queue;
  if (workers <= 1) {
    // Same steps on the calling thread: place, then solve, slice by slice.
    Slicer slicer(laplacian);
    for (size_t index = 0;; ++index) {
      const std::optional<SliceBounds> bounds = planner->next();
      if (!bounds) break;
      queue.push(*bounds);
      queue.store(index, slicer.solve_interval(bounds->lo, bounds->hi, slice_label(index)));
    }
    return queue.finish();
  }
  std::vector<std::thread> threads;
  threads.reserve(static_cast<size_t>(workers));
  for (int w = 0; w < workers; ++w) threads.emplace_back(work, std::cref(laplacian), &queue);
  size_t placed = 0;
  try {
    while (!queue.failed()) {
      const std::optional<SliceBounds> bounds = planner->next();
      if (!bounds) break;
      queue.push(*bounds);
      ++placed;
    }
  } catch (...) {
    // Sequentially this error would follow the solves of the slices below it.
    queue.fail(placed, std::current_exception());
  }
  queue.close();
  for (std::thread& t : threads) t.join();
  return queue.finish();
}

}  // namespace pleat
