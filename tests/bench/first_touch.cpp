// What the machine charges for memory a process touches for the first time: maps MB megabytes,
// asks for huge pages as the Delaunay stage does (core/memory.hpp), writes one byte a page from
// THREADS threads, unmaps; ROUNDS times, PAUSE seconds apart. On bare metal a round is the
// kernel zero-filling the pages (about 0.1 s a GB); in a virtual machine whose guest hands free
// memory back to the host (virtio-balloon free page reporting) the host must back every page
// again, and a round after a pause can cost ten times one straight after the last.
//   first_touch MB [THREADS=2] [ROUNDS=3] [PAUSE=30]
#include <sys/mman.h>

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "core/memory.hpp"

namespace {

double touch_seconds(std::size_t bytes, unsigned threads) {
  const auto start = std::chrono::steady_clock::now();
  void* map = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) {
    std::perror("mmap");
    std::exit(1);
  }
  auto* bytes_of = static_cast<volatile char*>(map);
  tincdt::advise_huge_pages(map, bytes);
  const std::size_t share = bytes / threads;
  std::vector<std::thread> workers;
  for (unsigned k = 0; k < threads; ++k)
    workers.emplace_back([=] {
      const std::size_t end = k + 1 == threads ? bytes : (k + 1) * share;
      for (std::size_t i = k * share; i < end; i += 4096) bytes_of[i] = 1;
    });
  for (std::thread& w : workers) w.join();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ::munmap(map, bytes);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 5) {
    std::fprintf(stderr, "usage: %s MB [THREADS=2] [ROUNDS=3] [PAUSE=30]\n", argv[0]);
    return 2;
  }
  const std::size_t mb = std::strtoull(argv[1], nullptr, 10);
  const auto threads = static_cast<unsigned>(argc > 2 ? std::atoi(argv[2]) : 2);
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 3;
  const int pause = argc > 4 ? std::atoi(argv[4]) : 30;
  if (mb == 0 || threads == 0 || rounds <= 0 || pause < 0) {
    std::fprintf(stderr, "%s: MB, THREADS and ROUNDS must be positive, PAUSE >= 0\n", argv[0]);
    return 2;
  }
  const std::size_t bytes = mb << 20;
  for (int r = 0; r < rounds; ++r) {
    if (r > 0) std::this_thread::sleep_for(std::chrono::seconds(pause));
    const double s = touch_seconds(bytes, threads);
    std::printf("round %d: %zu MB, %u threads: %.2f s (%.2f s a GB)\n", r + 1, mb, threads, s,
                s / (static_cast<double>(bytes) / 1e9));
  }
  return 0;
}
