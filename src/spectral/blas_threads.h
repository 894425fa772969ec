#pragma once
// Pins OpenBLAS to one thread for a scope. The slicing solver runs its own
// workers, and OpenBLAS splitting each small GEMV across the same cores only
// adds spinning (measured: half the profile in sched_yield); one BLAS thread
// also makes every reduction order independent of the worker count. Scopes
// nest and overlap across threads safely (reference-counted).
namespace pleat {

class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

}  // namespace pleat
