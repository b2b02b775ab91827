// Threads kept for a whole computation, so that splitting a few thousand items between cores
// costs microseconds, not a thread start: run(f, chunks) calls f(c, chunks) once for every chunk
// c in [0, chunks). The calling thread and the workers claim chunks in turn, so a worker that is
// late (asleep, or descheduled on a busy machine) only means the caller runs more of them; what
// a chunk computes must therefore not depend on the thread that runs it. Idle workers spin
// briefly for the next job, then sleep on a futex. One run at a time: run() is not reentrant
// and a pool is driven by one thread. The thread count is the caller's (tincdt::thread_count of
// its --threads), never a global.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace tincdt {

class ThreadPool {
 public:
  // THREADS in all, the calling thread included (0 counts as 1): THREADS - 1 workers.
  explicit ThreadPool(std::size_t threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  std::size_t threads() const { return workers_.size() + 1; }

  // Calls f(c, chunks) for every chunk c and returns when all have run. An exception thrown by
  // a chunk does not stop the others; once all have run, the first one caught is rethrown.
  // One chunk, or no worker: all chunks run in order on the calling thread.
  template <class F>
  void run(F& f, std::size_t chunks) {
    if (chunks <= 1 || workers_.empty()) {
      for (std::size_t c = 0; c < chunks; ++c) f(c, chunks);
      return;
    }
    dispatch(&call<F>, &f, chunks, nullptr, nullptr, {});
  }

  // The same, and while the calling thread has no chunk left to claim but others still run,
  // it calls waiting() about every PERIOD (from the calling thread only: for progress reports
  // of long chunks).
  template <class F, class W>
  void run(F& f, std::size_t chunks, W& waiting, std::chrono::milliseconds period) {
    if (chunks <= 1 || workers_.empty()) {
      for (std::size_t c = 0; c < chunks; ++c) f(c, chunks);
      return;
    }
    dispatch(&call<F>, &f, chunks, &wait_call<W>, &waiting, period);
  }

 private:
  using Job = void (*)(void*, std::size_t, std::size_t);
  using Waiting = void (*)(void*);

  template <class F>
  static void call(void* f, std::size_t c, std::size_t chunks) {
    (*static_cast<F*>(f))(c, chunks);
  }
  template <class W>
  static void wait_call(void* w) {
    (*static_cast<W*>(w))();
  }

  void dispatch(Job job, void* fn, std::size_t chunks, Waiting waiting, void* waiting_fn,
                std::chrono::milliseconds period);
  void claim_all();
  void work();
  void stop();

  std::vector<std::thread> workers_;
  std::atomic<std::uint64_t> generation_{0};    // one more for every job, and for the stop
  std::atomic<std::size_t> next_{0}, done_{0};  // the next chunk to claim; chunks that have run
  std::atomic<bool> stop_{false};
  // The job: written before next_ is reset (release), read after a chunk is claimed (acquire).
  Job job_ = nullptr;
  void* fn_ = nullptr;
  std::size_t chunks_ = 0;
  std::mutex error_mutex_;
  std::exception_ptr error_;  // the first a chunk threw
};

}  // namespace tincdt
