// Decodes every point of a LAZ file (coordinates, classification, returns) R times with
// tincdt's decoder and prints the best time, in the same terms as
// ../shared/bench/node/lazperf_decode.mjs so that compare_lazperf.sh can put them side by side:
//   laz_bench FILE.laz [--threads N] [--repeat R]
//   RESULT points=N threads=T best_s=S points_per_s=P checksum=C
// checksum: the sum of the raw X, Y and Z integers of every point (laz-perf's is the same sum).
// threads: 0 (default) = one per core.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/laz_reader.hpp"

int main(int argc, char** argv) {
  std::string path;
  unsigned threads = 0;
  int repeat = 5;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc) {
      threads = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else if (arg == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else if (path.empty() && arg[0] != '-') {
      path = arg;
    } else {
      path.clear();
      break;
    }
  }
  if (path.empty() || repeat < 1) {
    std::fprintf(stderr, "usage: %s FILE.laz [--threads N] [--repeat R]\n", argv[0]);
    return 2;
  }
  const unsigned shown = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  try {
    const tincdt::io::detail::MappedFile file(path);
    std::vector<std::string> warnings;
    const tincdt::io::laz::LazSource source =
        tincdt::io::laz::open_laz(path, file.data(), file.size(), warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    tincdt::io::laz::LazSummary summary;
    double best = 1e300;
    for (int r = 0; r < repeat; ++r) {
      const auto start = std::chrono::steady_clock::now();
      summary = tincdt::io::laz::summarize(source, threads, warnings);
      const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
      best = std::min(best, took.count());
    }
    std::uint64_t classes = 0;
    for (std::uint64_t c : summary.class_counts) classes += c != 0 ? 1 : 0;
    std::fprintf(stderr, "%s: %llu points, %llu classes, %llu first and %llu last returns\n",
                 path.c_str(), static_cast<unsigned long long>(summary.points),
                 static_cast<unsigned long long>(classes),
                 static_cast<unsigned long long>(summary.first_returns),
                 static_cast<unsigned long long>(summary.last_returns));
    std::printf("RESULT points=%llu threads=%u best_s=%.4f points_per_s=%.0f checksum=%lld\n",
                static_cast<unsigned long long>(summary.points), shown, best,
                static_cast<double>(summary.points) / best,
                static_cast<long long>(summary.xyz_sum));
  } catch (const tincdt::Error& e) {
    std::fprintf(stderr, "laz_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
