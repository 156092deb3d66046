// Threads started once and kept for every call: a BatchSimulator stepped once per call (a
// learning loop's step) paid a thread start per call (~50 us against ~300 us of physics for
// 4096 mechanisms on two cores). parallel.h starts threads per call, for work that runs long.
#ifndef KANE_SIM_SIM_WORKER_POOL_H
#define KANE_SIM_SIM_WORKER_POOL_H

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace kane_sim {

class WorkerPool {
 public:
  // `workers` in all, this (the calling) thread being worker 0: workers - 1 threads start here
  // and wait. A thread the system refuses (a process or memory limit) leaves a smaller pool,
  // never a failure: size() says how many there are.
  explicit WorkerPool(unsigned workers);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1; }

  // work(k) for k = 0 .. count - 1, worker j taking k = j, j + size(), ... (as parallelFor);
  // returns when all are done. The first exception a worker throws is rethrown here once every
  // worker has finished. One call at a time.
  void forEach(std::size_t count, const std::function<void(std::size_t)>& work);

 private:
  void serve(unsigned worker);
  void runShare(unsigned worker);

  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  std::uint64_t generation_ = 0;  // one per forEach: a worker runs each generation once
  unsigned busy_ = 0;             // helper threads still working on this generation
  bool quitting_ = false;
  std::size_t count_ = 0;
  const std::function<void(std::size_t)>* work_ = nullptr;
  std::exception_ptr failure_;
  std::vector<std::thread> threads_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_WORKER_POOL_H
