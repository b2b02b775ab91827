// Splits [0, n) into one contiguous chunk per hardware thread and runs f(begin, end) on each.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace tincdt {

template <class F>
void parallel_chunks(std::size_t n, F&& f, std::size_t min_chunk = 1 << 16) {
  const std::size_t hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t chunks = std::clamp<std::size_t>(n / min_chunk, 1, hw);
  if (chunks == 1) {
    f(std::size_t{0}, n);
    return;
  }
  std::vector<std::thread> threads;
  threads.reserve(chunks - 1);
  for (std::size_t c = 1; c < chunks; ++c)
    threads.emplace_back([&f, c, chunks, n] { f(n * c / chunks, n * (c + 1) / chunks); });
  f(std::size_t{0}, n / chunks);
  for (auto& t : threads) t.join();
}

}  // namespace tincdt
