// The one place that starts threads. Every thread count is the caller's (from
// BuildOptions::threads down), never a global; 0 means one thread per core.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace tincdt {

// THREADS, or every core for 0.
inline std::size_t thread_count(std::size_t threads) {
  return threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

namespace detail {
// Joins the threads however the scope is left (a thread that fails to start throws).
struct JoinAll {
  std::vector<std::thread>& threads;
  ~JoinAll() {
    for (std::thread& t : threads)
      if (t.joinable()) t.join();
  }
};
}  // namespace detail

// Runs left() on the calling thread and right() on a new one, or, if not CONCURRENT, left() and
// then right(): for two halves of one job whose result must not depend on the thread count.
// Returns when both are done; rethrows left's exception, else right's (in turn, right() does not
// run once left() has thrown).
template <class Left, class Right>
void run_two(bool concurrent, Left&& left, Right&& right) {
  if (!concurrent) {
    left();
    right();
    return;
  }
  std::exception_ptr right_error;
  std::thread worker([&] {
    try {
      right();
    } catch (...) {
      right_error = std::current_exception();
    }
  });
  std::exception_ptr left_error;
  try {
    left();
  } catch (...) {
    left_error = std::current_exception();
  }
  worker.join();
  if (left_error) std::rethrow_exception(left_error);
  if (right_error) std::rethrow_exception(right_error);
}

// Runs work(w) for w in [0, WORKERS) at once, w = 0 on the calling thread (so that it can report
// progress: callbacks need not be thread-safe). For workers that take their tasks from a shared
// queue: a thread that cannot start is left out and the others take up its share. Returns when
// all are done; rethrows the exception of the lowest-numbered worker that threw.
template <class F>
void run_workers(std::size_t workers, F&& work) {
  workers = std::max<std::size_t>(workers, 1);
  std::vector<std::exception_ptr> errors(workers);
  const auto guarded = [&work, &errors](std::size_t w) {
    try {
      work(w);
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  {
    std::vector<std::thread> helpers;
    const detail::JoinAll join{helpers};
    helpers.reserve(workers - 1);
    for (std::size_t w = 1; w < workers; ++w) {
      try {
        helpers.emplace_back(guarded, w);
      } catch (const std::system_error&) {
        break;  // fewer threads than asked for
      }
    }
    guarded(0);
  }
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// The number of ranges parallel_parts splits N items into: one a thread (THREADS, 0 = one per
// core), each of at least MIN_PART items.
inline std::size_t part_count(std::size_t threads, std::size_t n, std::size_t min_part = 1 << 16) {
  return std::clamp<std::size_t>(n / std::max<std::size_t>(min_part, 1), 1, thread_count(threads));
}

// Runs f(part, begin, end) for the PARTS equal ranges of [0, n), each on a thread of its own (the
// first on the calling thread): for passes that count per range and then fill per range. Rethrows
// the exception of the lowest range that threw, the one a single pass over [0, n) meets first.
template <class F>
void parallel_parts(std::size_t parts, std::size_t n, F&& f) {
  parts = std::max<std::size_t>(parts, 1);
  std::vector<std::exception_ptr> errors(parts);
  std::atomic<std::size_t> next{0};
  run_workers(parts, [&](std::size_t) {
    for (std::size_t p; (p = next.fetch_add(1)) < parts;) {
      try {
        f(p, n * p / parts, n * (p + 1) / parts);
      } catch (...) {
        errors[p] = std::current_exception();
      }
    }
  });
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

// Splits [0, n) into at most THREADS chunks (0 = one per core) of at least MIN_CHUNK items each
// and runs f(begin, end) on each, as parallel_parts does (errors included).
template <class F>
void parallel_chunks(std::size_t threads, std::size_t n, F&& f, std::size_t min_chunk = 1 << 16) {
  parallel_parts(part_count(threads, n, min_chunk), n,
                 [&f](std::size_t, std::size_t begin, std::size_t end) { f(begin, end); });
}

// A job started now and waited for later: on a thread of its own if CONCURRENT, else at once on
// the calling thread. wait() returns when it is done and rethrows its exception; the destructor
// waits too (and drops the exception).
class BackgroundJob {
 public:
  template <class F>
  BackgroundJob(bool concurrent, F&& job) {
    if (concurrent) {
      thread_ = std::thread([this, job = std::forward<F>(job)]() mutable { guarded(job); });
    } else {
      guarded(job);
    }
  }
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  ~BackgroundJob() {
    if (thread_.joinable()) thread_.join();
  }
  void wait() {
    if (thread_.joinable()) thread_.join();
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  template <class F>
  void guarded(F& job) noexcept {
    try {
      job();
    } catch (...) {
      error_ = std::current_exception();
    }
  }
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace tincdt
