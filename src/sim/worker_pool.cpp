// A pool of threads that spin briefly, then wait (condition variables), between many short calls.
#include "kane_sim/sim/worker_pool.h"

#include <unistd.h>

#include <system_error>

namespace kane_sim {

WorkerPool::WorkerPool(unsigned workers, std::chrono::microseconds spin)
    : spin_(spin), owner_(static_cast<long>(getpid())) {
  for (unsigned j = 1; j < workers; ++j) {
    try {
      threads_.emplace_back([this] { serve(); });
    } catch (const std::system_error&) {
      break;  // a smaller pool: every item is still done, by the threads there are
    }
  }
}

bool WorkerPool::forked() const { return static_cast<long>(getpid()) != owner_; }

WorkerPool::~WorkerPool() {
  if (forked()) {
    // The handles name threads of the parent; a joinable std::thread must not be destroyed, and
    // the mutex may have been held by a helper at the fork: leave both to the process's exit.
    new std::vector<std::thread>(std::move(threads_));
    static_cast<void>(sync_.release());
    return;
  }
  {
    std::lock_guard<std::mutex> lock(sync_->mutex);
    quitting_ = true;
  }
  generation_.fetch_add(1);  // ends a spin
  sync_->wake.notify_all();
  for (std::thread& t : threads_) t.join();
}

void WorkerPool::runShare() {
  try {
    for (std::size_t k = next_.fetch_add(1); k < count_; k = next_.fetch_add(1)) (*work_)(k);
  } catch (...) {
    std::lock_guard<std::mutex> lock(sync_->mutex);
    if (!failure_) failure_ = std::current_exception();
    next_.store(count_);  // the items not yet taken are not started
  }
}

void WorkerPool::serve() {
  std::uint64_t seen = generation_.load();
  for (;;) {
    const auto until = std::chrono::steady_clock::now() + spin_;
    while (generation_.load(std::memory_order_acquire) == seen &&
           std::chrono::steady_clock::now() < until) {
      std::this_thread::yield();
    }
    {
      std::unique_lock<std::mutex> lock(sync_->mutex);
      sync_->wake.wait(lock, [&] { return quitting_ || generation_.load() != seen; });
      if (quitting_) return;
      seen = generation_.load();
      if (!open_) continue;  // woke after that call ended: nothing of it left to take
      ++joined_;
    }
    runShare();
    {
      std::lock_guard<std::mutex> lock(sync_->mutex);
      --joined_;
    }
    sync_->finished.notify_one();
  }
}

void WorkerPool::forEach(std::size_t count, const std::function<void(std::size_t)>& work) {
  if (threads_.empty() || count <= 1 || forked()) {
    for (std::size_t k = 0; k < count; ++k) work(k);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(sync_->mutex);
    count_ = count;
    work_ = &work;
    failure_ = nullptr;
    next_.store(0);
    open_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  sync_->wake.notify_all();
  runShare();
  std::exception_ptr failure;
  {
    std::unique_lock<std::mutex> lock(sync_->mutex);
    open_ = false;  // every item is taken: a helper waking now has nothing to join
    sync_->finished.wait(lock, [&] { return joined_ == 0; });
    work_ = nullptr;
    failure = failure_;
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace kane_sim
