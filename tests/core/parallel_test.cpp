// The thread module: chunking, the two-way split, worker pools and background jobs.
#include "core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using tincdt::BackgroundJob;
using tincdt::parallel_chunks;
using tincdt::parallel_parts;
using tincdt::part_count;
using tincdt::run_two;
using tincdt::run_workers;
using tincdt::thread_count;

TEST(ThreadCount, ZeroMeansEveryCoreAndOthersStay) {
  EXPECT_GE(thread_count(0), 1u);
  EXPECT_EQ(thread_count(1), 1u);
  EXPECT_EQ(thread_count(7), 7u);
}

TEST(ParallelChunks, CoversEveryItemOnce) {
  for (const std::size_t threads : {1, 3, 8}) {
    std::vector<int> seen(1000, 0);
    parallel_chunks(
        threads, seen.size(),
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t i = begin; i < end; ++i) ++seen[i];
        },
        10);
    EXPECT_EQ(std::accumulate(seen.begin(), seen.end(), 0), 1000) << threads;
    for (const int s : seen) ASSERT_EQ(s, 1);
  }
}

TEST(ParallelChunks, RethrowsTheLowestChunksErrorOnceAllHaveRun) {
  for (const std::size_t threads : {1, 4}) {
    std::atomic<int> ran{0};
    try {
      parallel_chunks(
          threads, 400,
          [&](std::size_t begin, std::size_t) {
            ++ran;
            if (begin > 0) throw std::runtime_error(std::to_string(begin));
          },
          100);
      if (threads > 1) FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "100");  // the error a single pass would meet first
    }
    EXPECT_EQ(ran, threads > 1 ? 4 : 1);
  }
}

TEST(ParallelParts, NumbersEqualRangesThatCoverEveryItem) {
  EXPECT_EQ(part_count(8, 1000, 100), 8u);
  EXPECT_EQ(part_count(8, 250, 100), 2u);
  EXPECT_EQ(part_count(8, 50, 100), 1u);
  std::vector<std::pair<std::size_t, std::size_t>> range(5);
  parallel_parts(5, 1003, [&](std::size_t part, std::size_t begin, std::size_t end) {
    range[part] = {begin, end};
  });
  std::size_t at = 0;
  for (const auto& [begin, end] : range) {
    EXPECT_EQ(begin, at);
    EXPECT_GE(end - begin, 200u);
    EXPECT_LE(end - begin, 201u);
    at = end;
  }
  EXPECT_EQ(at, 1003u);
}

TEST(RunTwo, RunsBothSidesEitherWay) {
  for (const bool concurrent : {false, true}) {
    int left = 0, right = 0;
    run_two(
        concurrent, [&] { left = 1; }, [&] { right = 2; });
    EXPECT_EQ(left, 1);
    EXPECT_EQ(right, 2);
  }
}

TEST(RunTwo, SequentialRunsLeftFirst) {
  std::vector<int> order;
  run_two(
      false, [&] { order.push_back(0); }, [&] { order.push_back(1); });
  EXPECT_EQ(order, (std::vector<int>{0, 1}));
}

TEST(RunTwo, RethrowsAfterBothFinishLeftFirst) {
  for (const bool concurrent : {false, true}) {
    std::atomic<bool> right_done{false};
    EXPECT_THROW(
        run_two(
            concurrent, [] { throw std::runtime_error("left"); }, [&] { right_done = true; }),
        std::runtime_error);
    EXPECT_EQ(right_done, concurrent);  // in turn, a failing left() ends the job
    try {
      run_two(
          concurrent, [] { throw std::runtime_error("left"); },
          [] { throw std::logic_error("right"); });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "left");
    }
    EXPECT_THROW(run_two(
                     concurrent, [] {}, [] { throw std::logic_error("right"); }),
                 std::logic_error);
  }
}

TEST(RunWorkers, EveryWorkerRunsOnceCallerFirst) {
  std::vector<std::atomic<int>> runs(4);
  std::thread::id first;
  run_workers(4, [&](std::size_t w) {
    ++runs[w];
    if (w == 0) first = std::this_thread::get_id();
  });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  EXPECT_EQ(first, std::this_thread::get_id());
}

TEST(RunWorkers, RethrowsTheLowestWorkersException) {
  try {
    run_workers(3, [](std::size_t w) {
      if (w > 0) throw std::runtime_error(std::to_string(w));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "1");
  }
}

TEST(BackgroundJob, WaitGivesTheResultAndTheError) {
  for (const bool concurrent : {false, true}) {
    int value = 0;
    BackgroundJob job(concurrent, [&] { value = 5; });
    job.wait();
    EXPECT_EQ(value, 5);
    BackgroundJob failing(concurrent, [] { throw std::runtime_error("job"); });
    EXPECT_THROW(failing.wait(), std::runtime_error);
    EXPECT_NO_THROW(failing.wait());  // the error is given once
  }
}

}  // namespace
