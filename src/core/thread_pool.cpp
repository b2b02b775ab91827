#include "core/thread_pool.hpp"

#include <cassert>
#include <utility>

namespace tincdt {
namespace {

// Spins of the wait loops, with a pause each: some tens of microseconds before a futex sleep.
constexpr int kSpins = 4000;
// The calling thread's sleep between looks at the chunks while it reports progress.
constexpr std::chrono::milliseconds kNap{1};

inline void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

ThreadPool::ThreadPool(std::size_t threads) {
  try {
    for (std::size_t i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
  } catch (...) {  // no thread to be had: the ones started go before the error does
    stop();
    throw;
  }
}

ThreadPool::~ThreadPool() {
  stop();
}

void ThreadPool::stop() {
  stop_ = true;
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
}

void ThreadPool::dispatch(Job job, void* fn, std::size_t chunks, Waiting waiting, void* waiting_fn,
                          std::chrono::milliseconds period) {
  assert(chunks > 1 && !workers_.empty());
  job_ = job;
  fn_ = fn;
  chunks_ = chunks;
  done_.store(0, std::memory_order_relaxed);
  // A worker still leaving the last job may claim from next_ at once: the release makes the
  // job's fields above visible to it.
  next_.store(0, std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  claim_all();
  auto last_call = std::chrono::steady_clock::now();
  for (int spin = 0;; ++spin) {
    const std::size_t done = done_.load(std::memory_order_acquire);
    if (done == chunks) break;
    assert(done < chunks);
    if (spin <= kSpins) {
      cpu_relax();
    } else if (waiting) {
      // Short naps, so that the last chunk's end is seen within one, not within a period.
      std::this_thread::sleep_for(kNap);
      const auto now = std::chrono::steady_clock::now();
      if (now - last_call >= period && done_.load(std::memory_order_acquire) != chunks) {
        waiting(waiting_fn);
        last_call = now;
      }
    } else {
      done_.wait(done, std::memory_order_acquire);
    }
  }
  std::exception_ptr error = std::exchange(error_, nullptr);
  if (error) std::rethrow_exception(error);
}

// Runs chunks until none is left to claim.
void ThreadPool::claim_all() {
  for (;;) {
    const std::size_t c = next_.fetch_add(1, std::memory_order_acquire);
    if (c >= chunks_) return;
    try {
      job_(fn_, c, chunks_);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(error_mutex_);
      if (!error_) error_ = std::current_exception();
    }
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks_) done_.notify_all();
  }
}

void ThreadPool::work() {
  std::uint64_t seen = 0;
  for (;;) {
    for (int spin = 0;; ++spin) {
      const std::uint64_t g = generation_.load(std::memory_order_acquire);
      if (g != seen) {
        seen = g;
        break;
      }
      if (spin > kSpins)
        generation_.wait(g, std::memory_order_acquire);
      else
        cpu_relax();
    }
    if (stop_) return;
    claim_all();
  }
}

}  // namespace tincdt
