// A pool of threads that wait between calls (condition variables), for many short calls.
#include "kane_sim/sim/worker_pool.h"

#include <system_error>

namespace kane_sim {

WorkerPool::WorkerPool(unsigned workers) {
  for (unsigned j = 1; j < workers; ++j) {
    try {
      threads_.emplace_back([this, j] { serve(j); });
    } catch (const std::system_error&) {
      break;  // a smaller pool: every item is still done, by the threads there are
    }
  }
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    quitting_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void WorkerPool::runShare(unsigned worker) {
  try {
    for (std::size_t k = worker; k < count_; k += size()) (*work_)(k);
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!failure_) failure_ = std::current_exception();
  }
}

void WorkerPool::serve(unsigned worker) {
  std::uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return quitting_ || generation_ != seen; });
      if (quitting_) return;
      seen = generation_;
    }
    runShare(worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    finished_.notify_one();
  }
}

void WorkerPool::forEach(std::size_t count, const std::function<void(std::size_t)>& work) {
  if (threads_.empty() || count <= 1) {
    for (std::size_t k = 0; k < count; ++k) work(k);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    count_ = count;
    work_ = &work;
    failure_ = nullptr;
    busy_ = static_cast<unsigned>(threads_.size());
    ++generation_;
  }
  wake_.notify_all();
  runShare(0);
  std::exception_ptr failure;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    finished_.wait(lock, [&] { return busy_ == 0; });
    work_ = nullptr;
    failure = failure_;
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace kane_sim
