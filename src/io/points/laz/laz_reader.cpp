#include "io/points/laz/laz_reader.hpp"

#include <algorithm>
#include <array>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <vector>

#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "io/points/laz/chunk.hpp"
#include "io/points/laz/chunk_table.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/point10_decoder.hpp"
#include "io/points/laz/point14_decoder.hpp"
#include "io/points/load_le.hpp"

namespace tincdt::io::laz {
namespace {

// A point count is trusted for a reservation only up to this many points per compressed byte
// (real LiDAR takes 2 to 10 bytes per point): a header or table that claims more cannot make the
// reader allocate more; the vectors then grow as points are actually decoded.
constexpr std::uint64_t kPlausiblePointsPerByte = 16;

std::size_t plausible(std::uint64_t points, std::uint64_t bytes) {
  return static_cast<std::size_t>(std::min(points, bytes * kPlausiblePointsPerByte));
}

struct Prepared {
  PointLayout layout;
  ChunkPlan plan;
  // A COPC read by box: the nodes decoded, one per chunk of the plan, and their names.
  std::vector<CopcNode> nodes;
  std::vector<std::string> names;
};

PointLayout layout_of(const LazSource& src) {
  const LaszipVlr vlr = parse_laszip_vlr(src.path, src.laszip_vlr, src.laszip_vlr_size);
  return check_layout(src.path, vlr, src.point_format, src.record_length);
}

Prepared prepare(const LazSource& src, std::vector<std::string>& warnings) {
  Prepared p;
  p.layout = layout_of(src);
  if (p.layout.waveform && !p.layout.layered) {
    // The waveform item sits in the same stream as the coordinates: it would have to be decoded.
    throw InputError(src.path, "LASzip VLR",
                     "LAZ point format " + std::to_string(src.point_format) +
                         " (with waveform packets) is not supported; formats 0-3 and 6-10 are");
  }
  PointData data;
  data.file = src.file;
  data.file_size = src.file_size;
  data.offset_to_points = src.offset_to_points;
  data.point_count = src.point_count;
  data.data_limit = src.data_limit;
  p.plan = plan_chunks(src.path, data, p.layout, warnings);
  return p;
}

// The chunks of the COPC nodes NODES (in file order). Each node's chunk must hold the points the
// hierarchy gives it: a whole read takes the chunk's own count.
Prepared prepare_copc(const LazSource& src, const PointLayout& layout,
                      std::vector<CopcNode> nodes) {
  Prepared p;
  p.layout = layout;
  p.plan.data_end = src.data_limit;
  std::uint64_t first = 0;
  for (const CopcNode& node : nodes) {
    const std::string name = "COPC node " + node.key.text() + ", byte " + count_text(node.offset);
    if (node.bytes < src.record_length + 4)
      throw InputError(src.path, name,
                       "its chunk of " + count_text(node.bytes) +
                           " bytes is too short for a first point and a point count");
    const std::uint64_t held = load_le<std::uint32_t>(src.file + node.offset + src.record_length);
    if (held != node.points)
      throw InputError(src.path, name,
                       "the hierarchy gives it " + count_text(node.points) +
                           " points, its chunk holds " + count_text(held));
    p.plan.chunks.push_back({node.offset, node.bytes, node.points, first});
    p.names.push_back(name);
    first += node.points;
  }
  p.nodes = std::move(nodes);
  return p;
}

ChunkInput input_for(const LazSource& src, const Prepared& prep, const ChunkEntry& c,
                     std::size_t index) {
  ChunkInput in;
  if (!prep.names.empty()) in.names = &prep.names;
  in.data = src.file + c.offset;
  in.size = static_cast<std::size_t>(c.size);
  in.points = c.points;
  in.path = &src.path;
  in.index = index;
  in.first_point = c.first_point;
  return in;
}

// Hands the pages of decoded chunks back to the kernel, front to back.
class PageReleaser {
 public:
  explicit PageReleaser(const LazSource& src) : mapping_(src.mapping) {}
  void up_to(std::uint64_t end) {
    if (mapping_ == nullptr || end <= released_) return;
    mapping_->release(static_cast<std::size_t>(released_), static_cast<std::size_t>(end));
    released_ = end;
  }

 private:
  const detail::MappedFile* mapping_;
  std::uint64_t released_ = 0;
};

// Decodes the chunks of a file without a chunk table: each starts where the previous one's data
// ended, so they go one after the other.
template <class Decoder, class Output, class Decode, class Commit>
void decode_in_sequence(const LazSource& src, const Prepared& prep, unsigned fields,
                        PageReleaser& releaser, Decode& decode, Commit& commit) {
  const ChunkPlan& plan = prep.plan;
  const std::size_t n = plan.chunks.size();
  Decoder decoder(prep.layout, fields);
  Output out;
  std::uint64_t offset = plan.chunks[0].offset;
  for (std::size_t c = 0; c < n; ++c) {
    ChunkEntry chunk = plan.chunks[c];
    chunk.offset = offset;
    chunk.size = plan.data_end - offset;
    offset += decode(decoder, input_for(src, prep, chunk, c), out);
    commit(out);
    releaser.up_to(offset);
  }
  if (plan.exact_end && offset != plan.data_end) {
    // Without the table nothing says where each chunk starts; a wrong chunk size shows here.
    throw InputError(src.path, "chunk " + count_text(n - 1),
                     "the chunks end at byte " + count_text(offset) +
                         " but the chunk table starts at byte " + count_text(plan.data_end) +
                         ": the file is damaged, or its LASzip VLR has the wrong chunk size");
  }
}

// Decodes the chunks of the table on THREADS threads (at least two). Workers take chunks in
// order; a finished chunk waits in a slot until the ones before it are committed. The window
// bounds how far ahead of the oldest unfinished chunk workers may run, and so the memory the
// waiting outputs hold.
template <class Decoder, class Output, class Decode, class Commit>
void decode_in_parallel(const LazSource& src, const Prepared& prep, unsigned fields,
                        std::size_t threads, PageReleaser& releaser, Decode& decode,
                        Commit& commit) {
  const ChunkPlan& plan = prep.plan;
  const std::size_t n = plan.chunks.size();
  const std::size_t window = 2 * threads;
  std::mutex mutex;
  std::condition_variable wake;
  std::size_t next = 0;
  std::size_t committed = 0;
  bool stop = false;
  std::size_t failed_chunk = n + 1;
  std::exception_ptr failure;
  std::vector<Output> slots(window);
  std::vector<char> ready(window, 0);

  const auto fail = [&](std::size_t chunk) {  // with the mutex held
    if (chunk < failed_chunk) {
      failed_chunk = chunk;
      failure = std::current_exception();
    }
    stop = true;  // no new chunks; those already taken, all before CHUNK, still finish
    wake.notify_all();
  };
  run_workers(threads, [&](std::size_t) {
    std::size_t chunk = n;
    try {
      Decoder decoder(prep.layout, fields);
      Output out;
      for (;;) {
        {
          std::unique_lock lock(mutex);
          wake.wait(lock, [&] { return stop || next >= n || next < committed + window; });
          if (stop || next >= n) return;
          chunk = next++;
        }
        decode(decoder, input_for(src, prep, plan.chunks[chunk], chunk), out);
        std::lock_guard lock(mutex);
        std::swap(slots[chunk % window], out);
        ready[chunk % window] = 1;
        while (committed < n && ready[committed % window]) {
          commit(slots[committed % window]);
          ready[committed % window] = 0;
          releaser.up_to(plan.chunks[committed].offset + plan.chunks[committed].size);
          ++committed;
        }
        wake.notify_all();
      }
    } catch (...) {
      std::lock_guard lock(mutex);
      fail(chunk);
    }
  });
  if (failure) std::rethrow_exception(failure);
}

// Decodes every chunk with one Decoder per thread. decode(decoder, input, output) turns a chunk
// into an Output; commit(output) consumes it. Commits happen one at a time and in chunk order,
// whatever the thread count, so the result is deterministic. When chunks fail, the error of the
// first failing chunk is thrown (every chunk before it has been decoded by then).
template <class Decoder, class Output, class Decode, class Commit>
void decode_chunks(const LazSource& src, const Prepared& prep, unsigned fields, unsigned threads,
                   Decode& decode, Commit& commit) {
  const ChunkPlan& plan = prep.plan;
  const std::size_t n = plan.chunks.size();
  if (n == 0) return;
  PageReleaser releaser(src);
  if (src.mapping != nullptr && prep.nodes.empty()) {  // a box read skips most of the data
    src.mapping->advise_sequential(static_cast<std::size_t>(src.offset_to_points),
                                   static_cast<std::size_t>(plan.data_end));
  }
  if (plan.sequential) {
    decode_in_sequence<Decoder, Output>(src, prep, fields, releaser, decode, commit);
    return;
  }
  const std::size_t workers = std::min<std::size_t>(thread_count(threads), n);
  if (workers > 1) {
    decode_in_parallel<Decoder, Output>(src, prep, fields, workers, releaser, decode, commit);
    return;
  }
  Decoder decoder(prep.layout, fields);
  Output out;
  for (std::size_t c = 0; c < n; ++c) {
    decode(decoder, input_for(src, prep, plan.chunks[c], c), out);
    commit(out);
    releaser.up_to(plan.chunks[c].offset + plan.chunks[c].size);
  }
}

template <class Output, class Decode, class Commit>
void decode_all(const LazSource& src, const Prepared& prep, unsigned fields, unsigned threads,
                Decode&& decode, Commit&& commit) {
  if (prep.layout.layered) {
    decode_chunks<Point14Decoder, Output>(src, prep, fields, threads, decode, commit);
  } else {
    decode_chunks<Point10Decoder, Output>(src, prep, fields, threads, decode, commit);
  }
}

// A box read trusts that every point lies in its node's cube: one that does not would be missed
// by the boxes it lies in, so the file cannot be read by box.
template <class Xyz>
void check_in_node(const LazSource& src, const CopcNode& node, const ChunkInput& in,
                   const std::vector<Xyz>& points) {
  const BBox& b = node.bounds;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point3 p = src.transform.apply(points[i][0], points[i][1], points[i][2]);
    if (p.x >= b.min_x && p.x <= b.max_x && p.y >= b.min_y && p.y <= b.max_y) continue;
    throw InputError(*in.path, (*in.names)[in.index],
                     "a point at (" + number_text(p.x) + ", " + number_text(p.y) +
                         ") lies outside the node's cube (x " + number_text(b.min_x) + " to " +
                         number_text(b.max_x) + ", y " + number_text(b.min_y) + " to " +
                         number_text(b.max_y) + "): the file cannot be read by box");
  }
}

std::uint64_t data_bytes(const LazSource& src) {
  return src.data_limit > src.offset_to_points ? src.data_limit - src.offset_to_points : 0;
}

}  // namespace

namespace {

// Decodes the chunks of PREP into OUT (see read_points), the figures into FIG and, when given,
// how many points each chunk gave into KEPT_PER_CHUNK.
std::uint64_t decode_points(const LazSource& src, const Prepared& prep, const PointFilter& filter,
                            unsigned threads, std::vector<Point3>& out, LazReadFigures& fig,
                            std::vector<std::uint64_t>* kept_per_chunk = nullptr) {
  for (const ChunkEntry& c : prep.plan.chunks) fig.points_decoded += c.points;
  if (fig.by_box) {
    for (const ChunkEntry& c : prep.plan.chunks) fig.chunk_bytes += c.size;
  } else {
    fig.chunk_bytes = data_bytes(src);
  }
  const detail::Selection sel(filter);
  using Xyz = std::array<std::int32_t, 3>;
  out.reserve(out.size() + plausible(fig.points_decoded, fig.chunk_bytes));
  detail::advise_huge_pages(out);
  std::uint64_t kept = 0;
  const auto decode = [&](auto& decoder, const ChunkInput& in, std::vector<Xyz>& buffer) {
    buffer.clear();
    buffer.reserve(plausible(in.points, in.size));
    std::size_t length = 0;
    if (sel.any()) {
      length = decoder.decode_chunk(in, [&](const auto& p) {
        if (sel.keeps(p.classification(), p.return_number(), p.number_of_returns())) {
          buffer.push_back({p.x(), p.y(), p.z()});
        }
      });
    } else {
      length = decoder.decode_chunk(in, [&](const auto& p) {
        buffer.push_back({p.x(), p.y(), p.z()});
      });
    }
    if (!prep.nodes.empty()) check_in_node(src, prep.nodes[in.index], in, buffer);
    return length;
  };
  const auto commit = [&](std::vector<Xyz>& buffer) {
    if (src.check_range) {
      for (std::size_t i = 0; i < buffer.size(); ++i) {
        const Point3 p = src.transform.apply(buffer[i][0], buffer[i][1], buffer[i][2]);
        // Without filters the points kept are the file's points, in order.
        src.transform.check_range(
            p, src.path, sel.any() || fig.by_box ? std::string() : "point " + count_text(kept + i));
      }
    }
    for (const Xyz& v : buffer) out.push_back(src.transform.apply(v[0], v[1], v[2]));
    kept += buffer.size();
    if (kept_per_chunk != nullptr) kept_per_chunk->push_back(buffer.size());
  };
  const unsigned fields = kCoordinates | (sel.filter_classes ? kClassification : 0u);
  decode_all<std::vector<Xyz>>(src, prep, fields, threads, decode, commit);
  return kept;
}

}  // namespace

std::uint64_t read_points(const LazSource& src, const PointFilter& filter, unsigned threads,
                          std::vector<Point3>& out, std::vector<std::string>& warnings,
                          LazReadFigures* figures) {
  LazReadFigures local;
  LazReadFigures& fig = figures != nullptr ? *figures : local;
  fig = {};
  if (filter.box && src.copc_info != nullptr) {
    // COPC requires formats 6-8, whose chunks state their point counts; other layouts are
    // read whole.
    const PointLayout layout = layout_of(src);
    if (layout.layered) {
      fig.by_box = true;
      CopcHierarchy h = read_hierarchy(src, &*filter.box);
      fig.hierarchy_bytes = h.page_bytes;
      return decode_points(src, prepare_copc(src, layout, std::move(h.nodes)), filter, threads, out,
                           fig);
    }
  }
  return decode_points(src, prepare(src, warnings), filter, threads, out, fig);
}

std::uint64_t read_nodes(const LazSource& src, std::vector<CopcNode> nodes,
                         const PointFilter& filter, unsigned threads, std::vector<Point3>& out,
                         LazReadFigures& figures, std::vector<std::uint64_t>* kept_per_node) {
  const PointLayout layout = layout_of(src);
  if (!layout.layered)
    throw InputError(src.path, "header",
                     "COPC needs point format 6, 7 or 8, not " + std::to_string(src.point_format));
  std::sort(nodes.begin(), nodes.end(),
            [](const CopcNode& a, const CopcNode& b) { return a.offset < b.offset; });
  figures = {};
  figures.by_box = true;
  return decode_points(src, prepare_copc(src, layout, std::move(nodes)), filter, threads, out,
                       figures, kept_per_node);
}

std::vector<std::uint8_t> read_records(const LazSource& src, unsigned threads,
                                       std::vector<std::string>& warnings) {
  const Prepared prep = prepare(src, warnings);
  if (prep.layout.waveform) {
    throw InputError(src.path, "",
                     "waveform packets are not decoded: whole records of point "
                     "format " +
                         std::to_string(src.point_format) + " cannot be read");
  }
  const std::size_t record = src.record_length;
  std::vector<std::uint8_t> records;
  records.reserve(plausible(src.point_count, data_bytes(src)) * record);
  const auto decode = [&](auto& decoder, const ChunkInput& in, std::vector<std::uint8_t>& buffer) {
    buffer.clear();
    buffer.reserve(plausible(in.points, in.size) * record);
    return decoder.decode_chunk(in, [&](const auto& p) {
      buffer.resize(buffer.size() + record);
      p.write_record(buffer.data() + buffer.size() - record);
    });
  };
  const auto commit = [&](std::vector<std::uint8_t>& buffer) {
    records.insert(records.end(), buffer.begin(), buffer.end());
  };
  decode_all<std::vector<std::uint8_t>>(src, prep, kEveryField, threads, decode, commit);
  return records;
}

LazSummary summarize(const LazSource& src, unsigned threads, std::vector<std::string>& warnings) {
  const Prepared prep = prepare(src, warnings);
  LazSummary total;
  const auto decode = [&](auto& decoder, const ChunkInput& in, LazSummary& s) {
    s = LazSummary{};
    return decoder.decode_chunk(in, [&](const auto& p) {
      ++s.points;
      s.xyz_sum += std::int64_t{p.x()} + p.y() + p.z();
      ++s.class_counts[p.classification() & 0xFFu];
      const unsigned r = p.return_number();
      const unsigned n = p.number_of_returns();
      const bool single = r == 0 || n == 0;
      s.first_returns += single || r == 1;
      s.last_returns += single || r >= n;
    });
  };
  const auto commit = [&](LazSummary& s) {
    total.points += s.points;
    total.xyz_sum += s.xyz_sum;
    total.first_returns += s.first_returns;
    total.last_returns += s.last_returns;
    for (int c = 0; c < 256; ++c) total.class_counts[c] += s.class_counts[c];
  };
  decode_all<LazSummary>(src, prep, kCoordinates | kClassification, threads, decode, commit);
  return total;
}

}  // namespace tincdt::io::laz
