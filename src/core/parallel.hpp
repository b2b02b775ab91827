// Splits [0, n) into one contiguous chunk per thread and runs f(begin, end) on each. The thread
// count is always the caller's (from BuildOptions::threads down), never a global.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace tincdt {

// THREADS, or every core for 0.
inline std::size_t thread_count(std::size_t threads) {
  return threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
}

// At most THREADS chunks (0 = one per core) of at least MIN_CHUNK items each; f runs on the
// calling thread for the first chunk.
template <class F>
void parallel_chunks(std::size_t threads, std::size_t n, F&& f, std::size_t min_chunk = 1 << 16) {
  const std::size_t chunks = std::clamp<std::size_t>(n / min_chunk, 1, thread_count(threads));
  if (chunks == 1) {
    f(std::size_t{0}, n);
    return;
  }
  std::vector<std::thread> workers;
  workers.reserve(chunks - 1);
  for (std::size_t c = 1; c < chunks; ++c)
    workers.emplace_back([&f, c, chunks, n] { f(n * c / chunks, n * (c + 1) / chunks); });
  f(std::size_t{0}, n / chunks);
  for (auto& t : workers) t.join();
}

}  // namespace tincdt
