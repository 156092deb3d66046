// Threads started once and kept for every call: a BatchSimulator stepped once per call (a
// learning loop's step) paid a thread start per call (~50 us against ~300 us of physics for
// 4096 mechanisms on two cores). parallel.h starts threads per call, for work that runs long.
#ifndef KANE_SIM_SIM_WORKER_POOL_H
#define KANE_SIM_SIM_WORKER_POOL_H

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace kane_sim {

class WorkerPool {
 public:
  // `workers` in all, this (the calling) thread being worker 0: workers - 1 threads start here
  // and wait. A thread the system refuses (a process or memory limit) leaves a smaller pool,
  // never a failure: size() says how many there are. After a call a helper spins (yielding)
  // for `spin` before it sleeps: a loop's next call, microseconds later, finds it awake
  // (measured, n = 4096 at one step a call on two AVX2 cores: 27 M mechanism-steps/s without,
  // 29 M with 30-300 us). The spinning costs at most `spin` of one core per call.
  explicit WorkerPool(unsigned workers,
                      std::chrono::microseconds spin = std::chrono::microseconds(50));
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1; }

  // work(k) for each k = 0 .. count - 1 once, each taken by the next free worker (this thread
  // included): a helper that wakes late costs the items it does not take, never the call's
  // wait. Returns when all are done. The first exception a worker throws is rethrown here once
  // every worker has finished its item. One call at a time.
  // In a process forked from the one that built the pool (Python's multiprocessing forks) the
  // helpers do not exist: this thread does every item, and the destructor leaves the helpers'
  // handles and the pool's mutex and condition variables alone (joining them aborted the child;
  // destroying a condition variable a helper waited on in the parent hung it).
  void forEach(std::size_t count, const std::function<void(std::size_t)>& work);

 private:
  void serve();
  void runShare();

  bool forked() const;

  const std::chrono::microseconds spin_;
  const long owner_;  // the process that started the helpers (getpid)
  // Held by pointer: in a forked child a condition variable a parent's helper waited on cannot
  // be destroyed (pthread_cond_destroy waits for that waiter), so the child leaves them be.
  struct Sync {
    std::mutex mutex;
    std::condition_variable wake, finished;
  };
  std::unique_ptr<Sync> sync_ = std::make_unique<Sync>();
  std::atomic<std::uint64_t> generation_{0};  // one per forEach
  std::atomic<std::size_t> next_{0};          // the next item to take
  bool open_ = false;                         // a forEach is under way and helpers may join it
  unsigned joined_ = 0;                       // helpers working on this forEach's items
  bool quitting_ = false;
  std::size_t count_ = 0;
  const std::function<void(std::size_t)>* work_ = nullptr;
  std::exception_ptr failure_;
  std::vector<std::thread> threads_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_WORKER_POOL_H
