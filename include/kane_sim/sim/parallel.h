// Work spread over threads, one helper for the package: the sweep runner, BatchSimulator and the
// Python module's batched rates all start their threads here. This thread is worker 0 (a call on
// one thread starts none); a thread the system refuses (a process or memory limit) is reported and
// its work done by those that did start; a worker's exception reaches the caller once every
// worker has finished (never std::terminate).
#ifndef KANE_SIM_SIM_PARALLEL_H
#define KANE_SIM_SIM_PARALLEL_H

#include <algorithm>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace kane_sim {

// One thread per core the system reports (at least 1).
inline unsigned coreCount() { return std::max(1u, std::thread::hardware_concurrency()); }

// Runs worker(j) for j = 0 .. started - 1, worker 0 on this thread, and returns `started`: the
// workers asked for, or fewer when the system refused a thread (on_shortfall is told why; the
// callers' workers take their work from a shared counter or a stride of `started`, so nothing
// is lost). `worker_count` 0 is taken as 1.
template <class Worker>
unsigned runWorkers(
    unsigned worker_count, Worker worker,
    const std::function<void(unsigned started, const std::string& why)>& on_shortfall = nullptr) {
  worker_count = std::max(1u, worker_count);
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto guarded = [&](unsigned j) {
    try {
      worker(j);
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> threads;
  unsigned started = 1;
  for (unsigned j = 1; j < worker_count; ++j) {
    try {
      threads.emplace_back(guarded, j);
      ++started;
    } catch (const std::system_error& e) {
      if (on_shortfall) on_shortfall(started, e.what());
      break;
    }
  }
  guarded(0);
  for (std::thread& t : threads) t.join();
  if (failure) std::rethrow_exception(failure);
  return started;
}

// work(k) for k = 0 .. count - 1 on up to `threads` threads, k taken in strides (thread j does
// j, j + n, ...: neighbouring items, often of similar cost, go to different threads). The
// number of threads is decided before any starts, so a refused thread's items are done here.
template <class Work>
void parallelFor(std::size_t count, unsigned threads, const Work& work) {
  const unsigned wanted =
      static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(threads, count)));
  if (wanted <= 1) {
    for (std::size_t k = 0; k < count; ++k) work(k);
    return;
  }
  const unsigned started = runWorkers(wanted, [&](unsigned j) {
    for (std::size_t k = j; k < count; k += wanted) work(k);
  });
  for (unsigned j = started; j < wanted; ++j)  // refused threads' strides, here
    for (std::size_t k = j; k < count; k += wanted) work(k);
}

// range(begin, end) over [0, count) cut into one contiguous block per thread (for work whose
// items cost the same and sit in one array: each thread streams its own block).
template <class Range>
void parallelBlocks(long count, unsigned threads, const Range& range) {
  const long blocks = std::max(1L, std::min<long>(threads, count));
  const long size = (count + blocks - 1) / std::max(1L, blocks);
  parallelFor(static_cast<std::size_t>(blocks), static_cast<unsigned>(blocks), [&](std::size_t b) {
    const long begin = std::min(count, static_cast<long>(b) * size);
    range(begin, std::min(count, begin + size));
  });
}

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_PARALLEL_H
