// ThreadPool: every chunk runs exactly once per run, over many runs in a row; a chunk's
// exception reaches the caller once all chunks have run; the waiting hook runs on the calling
// thread while other threads finish, and the run ends when they do; one thread (or one chunk) runs
// in order on the caller.
#include "core/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

namespace tincdt {
namespace {

TEST(ThreadPool, EveryChunkRunsOnceInManyRunsInARow) {
  ThreadPool pool(4);
  EXPECT_EQ(pool.threads(), 4u);
  for (std::size_t chunks : {1u, 2u, 3u, 7u, 16u, 100u}) {
    for (int round = 0; round < 200; ++round) {
      std::vector<std::atomic<int>> ran(chunks);
      auto f = [&](std::size_t c, std::size_t n) {
        EXPECT_EQ(n, chunks);
        ran[c].fetch_add(1);
      };
      pool.run(f, chunks);
      for (std::size_t c = 0; c < chunks; ++c) ASSERT_EQ(ran[c].load(), 1) << c;
    }
  }
}

TEST(ThreadPool, ResultsDoNotDependOnTheThreadCount) {
  std::vector<long> data(100'000);
  std::iota(data.begin(), data.end(), 0);
  const auto sums = [&](std::size_t threads) {
    ThreadPool pool(threads);
    std::vector<long> sum(16, 0);
    auto f = [&](std::size_t c, std::size_t n) {
      for (std::size_t i = data.size() * c / n; i < data.size() * (c + 1) / n; ++i)
        sum[c] += data[i];
    };
    pool.run(f, sum.size());
    return sum;
  };
  EXPECT_EQ(sums(1), sums(3));
  EXPECT_EQ(sums(0), sums(8));
}

TEST(ThreadPool, OneThreadRunsTheChunksInOrderOnTheCaller) {
  ThreadPool pool(1);
  EXPECT_EQ(pool.threads(), 1u);
  std::vector<std::size_t> order;
  const auto caller = std::this_thread::get_id();
  auto f = [&](std::size_t c, std::size_t) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    order.push_back(c);
  };
  pool.run(f, 5);
  EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

TEST(ThreadPool, AChunksErrorReachesTheCallerAfterAllChunksRan) {
  ThreadPool pool(3);
  std::atomic<int> ran{0};
  auto f = [&](std::size_t c, std::size_t) {
    ran.fetch_add(1);
    if (c == 5) throw std::runtime_error("chunk 5");
  };
  EXPECT_THROW(pool.run(f, 12), std::runtime_error);
  EXPECT_EQ(ran.load(), 12);
  // The pool goes on working after an error.
  ran = 0;
  auto g = [&](std::size_t, std::size_t) { ran.fetch_add(1); };
  pool.run(g, 12);
  EXPECT_EQ(ran.load(), 12);
}

// The chunk function of a run of two chunks that gives the worker one: the caller's chunk waits
// (up to 10 s) for the worker to take the other, which sets WORKER_IN and runs WORK.
template <class Work>
auto two_chunks_one_each(std::thread::id caller, std::atomic<bool>& worker_in, Work work) {
  return [caller, &worker_in, work](std::size_t, std::size_t) {
    if (std::this_thread::get_id() == caller) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (!worker_in && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      return;
    }
    worker_in = true;
    work();
  };
}

TEST(ThreadPool, WaitingRunsOnTheCallerWhileOthersFinish) {
  ThreadPool pool(2);
  const auto caller = std::this_thread::get_id();
  std::atomic<bool> worker_in{false}, release{false};
  std::atomic<int> waits{0};
  // The worker's chunk holds its thread until the caller has waited three times.
  auto f = two_chunks_one_each(caller, worker_in, [&] {
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  auto waiting = [&] {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    if (waits.fetch_add(1) + 1 >= 3) release = true;
  };
  pool.run(f, 2, waiting, std::chrono::milliseconds(2));
  EXPECT_TRUE(worker_in.load());
  EXPECT_GE(waits.load(), 3);
}

TEST(ThreadPool, ReturnsWhenTheLastChunkEndsNotAPeriodLater) {
  ThreadPool pool(2);
  const auto caller = std::this_thread::get_id();
  // The worker's chunk outlasts the caller's spins; the period is far longer than the run.
  std::atomic<bool> worker_in{false};
  auto f = two_chunks_one_each(caller, worker_in,
                               [] { std::this_thread::sleep_for(std::chrono::milliseconds(50)); });
  int waits = 0;
  auto waiting = [&] { ++waits; };
  const auto start = std::chrono::steady_clock::now();
  pool.run(f, 2, waiting, std::chrono::seconds(30));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(15));
  EXPECT_TRUE(worker_in.load());
  EXPECT_EQ(waits, 0);
}

}  // namespace
}  // namespace tincdt
