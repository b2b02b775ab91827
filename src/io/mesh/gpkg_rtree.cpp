#include "io/mesh/gpkg_rtree.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"

namespace tincdt::io::detail {
namespace {

constexpr std::size_t kCellBytes = 8 + 4 * 4;  // id, then min x, max x, min y, max y
constexpr std::size_t kNodesPerStatement = 64;

// Outward float32 rounding: the stored box always holds the true one.
float down(double v) {
  if (!(v > -FLT_MAX)) return -INFINITY;
  if (v > FLT_MAX) return FLT_MAX;
  float f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -INFINITY);
  return f;
}
float up(double v) {
  if (!(v < FLT_MAX)) return INFINITY;
  if (v < -FLT_MAX) return -FLT_MAX;
  float f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, INFINITY);
  return f;
}

struct Box {
  float min_x = INFINITY, max_x = -INFINITY, min_y = INFINITY, max_y = -INFINITY;
  void add(const Box& b) {
    min_x = std::min(min_x, b.min_x);
    max_x = std::max(max_x, b.max_x);
    min_y = std::min(min_y, b.min_y);
    max_y = std::max(max_y, b.max_y);
  }
};

// SQL runs through GDAL's connection; a statement that fails leaves GDAL's error.
bool run(GDALDataset& ds, const std::string& sql) {
  CPLErrorReset();
  OGRLayer* result = ds.ExecuteSQL(sql.c_str(), nullptr, nullptr);
  if (result != nullptr) ds.ReleaseResultSet(result);
  return CPLGetLastErrorType() != CE_Failure && CPLGetLastErrorType() != CE_Fatal;
}

// The integer columns of the first row of a query, or empty when it fails or has no row.
std::vector<std::int64_t> first_row(GDALDataset& ds, const std::string& sql) {
  std::vector<std::int64_t> values;
  CPLErrorReset();
  OGRLayer* result = ds.ExecuteSQL(sql.c_str(), nullptr, nullptr);
  if (result == nullptr) return values;
  const OgrFeature row(result->GetNextFeature());
  if (row)
    for (int i = 0; i < row->GetFieldCount(); ++i)
      values.push_back(row->IsFieldNull(i) ? -1 : row->GetFieldAsInteger64(i));
  ds.ReleaseResultSet(result);
  return values;
}

// Nodes in SQL: INSERT OR REPLACE INTO <name>_node VALUES (n, x'...'), (n, x'...'), ...
class NodeWriter {
 public:
  NodeWriter(GDALDataset& ds, const std::string& table, std::size_t node_bytes)
      : ds_(ds), insert_("INSERT OR REPLACE INTO \"" + table + "\" VALUES "), blob_(node_bytes) {}

  // Node NODENO at DEPTH (written in the root only) with CELLS of (id, box).
  bool add(std::int64_t nodeno, int depth, const std::vector<std::pair<std::int64_t, Box>>& cells) {
    std::fill(blob_.begin(), blob_.end(), 0);
    std::uint8_t* p = blob_.data();
    p = put(p, static_cast<std::uint64_t>(nodeno == 1 ? depth : 0), 2);
    p = put(p, cells.size(), 2);
    for (const auto& [id, box] : cells) {
      p = put(p, static_cast<std::uint64_t>(id), 8);
      for (const float f : {box.min_x, box.max_x, box.min_y, box.max_y}) {
        std::uint32_t bits;
        std::memcpy(&bits, &f, sizeof bits);
        p = put(p, bits, 4);
      }
    }
    sql_.append(sql_.empty() ? insert_ : ",").append("(").append(std::to_string(nodeno));
    sql_.append(",x'");
    static constexpr char kHex[] = "0123456789ABCDEF";
    for (const std::uint8_t b : blob_) {
      sql_ += kHex[b >> 4];
      sql_ += kHex[b & 15];
    }
    sql_ += "')";
    return ++pending_ < kNodesPerStatement || flush();
  }
  bool flush() {
    if (pending_ == 0) return true;
    const bool ok = run(ds_, sql_);
    sql_.clear();
    pending_ = 0;
    return ok;
  }

 private:
  static std::uint8_t* put(std::uint8_t* p, std::uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
    return p;
  }

  GDALDataset& ds_;
  std::string insert_;
  std::vector<std::uint8_t> blob_;
  std::string sql_;
  std::size_t pending_ = 0;
};

// The specification's triggers (GeoPackage 1.2, F.3), for table T, geometry column G, index R,
// and the fid column I.
std::vector<std::string> triggers(const std::string& t, const std::string& g, const std::string& r,
                                  const std::string& i) {
  const std::string on = " ON \"" + t + "\" ", into = "INSERT OR REPLACE INTO \"" + r + "\" ",
                    values = "VALUES (NEW.\"" + i + "\",ST_MinX(NEW.\"" + g +
                             "\"), ST_MaxX(NEW.\"" + g + "\"),ST_MinY(NEW.\"" + g +
                             "\"), ST_MaxY(NEW.\"" + g + "\")); ",
                    set = "NEW.\"" + g + "\" NOTNULL AND NOT ST_IsEmpty(NEW.\"" + g + "\")",
                    unset = "NEW.\"" + g + "\" ISNULL OR ST_IsEmpty(NEW.\"" + g + "\")",
                    same = "OLD.\"" + i + "\" = NEW.\"" + i + "\"",
                    moved = "OLD.\"" + i + "\" != NEW.\"" + i + "\"",
                    drop = "DELETE FROM \"" + r + "\" WHERE id = OLD.\"" + i + "\"; ";
  const std::string trigger = "CREATE TRIGGER \"" + r;
  return {
      trigger + "_insert\" AFTER INSERT" + on + "WHEN (" + set + ") BEGIN " + into + values + "END",
      trigger + "_update1\" AFTER UPDATE OF \"" + g + "\"" + on + "WHEN " + same + " AND (" + set +
          ") BEGIN " + into + values + "END",
      trigger + "_update2\" AFTER UPDATE OF \"" + g + "\"" + on + "WHEN " + same + " AND (" +
          unset + ") BEGIN " + drop + "END",
      trigger + "_update3\" AFTER UPDATE" + on + "WHEN " + moved + " AND (" + set + ") BEGIN " +
          drop + into + values + "END",
      trigger + "_update4\" AFTER UPDATE" + on + "WHEN " + moved + " AND (" + unset +
          ") BEGIN DELETE FROM \"" + r + "\" WHERE id IN (OLD.\"" + i + "\", NEW.\"" + i +
          "\"); END",
      trigger + "_delete\" AFTER DELETE" + on + "WHEN OLD.\"" + g + "\" NOT NULL BEGIN " + drop +
          "END",
  };
}

bool pack(GDALDataset& ds, const std::string& table, const std::string& column,
          const std::string& fid, std::uint64_t rows,
          const std::function<Envelope(std::uint64_t)>& envelope) {
  const std::string rtree = "rtree_" + table + "_" + column;
  if (!run(ds, "CREATE VIRTUAL TABLE \"" + rtree + "\" USING rtree(id, minx, maxx, miny, maxy)"))
    return false;
  // The module chose its node size when it made the (empty) root.
  const std::vector<std::int64_t> size =
      first_row(ds, "SELECT length(data) FROM \"" + rtree + "_node\" WHERE nodeno = 1");
  if (size.size() != 1 || size[0] < static_cast<std::int64_t>(4 + 2 * kCellBytes)) return false;
  const auto node_bytes = static_cast<std::size_t>(size[0]);
  const std::uint64_t fanout = (node_bytes - 4) / kCellBytes;

  // Level sizes, leaves first; nodes numbered from 2 level by level, the root (the one node of
  // the top level) 1.
  std::vector<std::uint64_t> level_nodes{std::max<std::uint64_t>(1, (rows + fanout - 1) / fanout)};
  while (level_nodes.back() > 1) level_nodes.push_back((level_nodes.back() + fanout - 1) / fanout);
  const int depth = static_cast<int>(level_nodes.size()) - 1;
  std::vector<std::int64_t> first_node(level_nodes.size());
  std::int64_t next = 2;
  for (std::size_t l = 0; l + 1 < level_nodes.size(); ++l) {
    first_node[l] = next;
    next += static_cast<std::int64_t>(level_nodes[l]);
  }
  first_node.back() = 1;

  // Level by level from the leaves: node n of a level holds its children n * fanout onwards,
  // the rows of a leaf, the nodes of the level below otherwise (each with its parent recorded).
  NodeWriter nodes(ds, rtree + "_node", node_bytes);
  const std::string insert_parent = "INSERT INTO \"" + rtree + "_parent\" VALUES ";
  std::string parents;
  std::vector<std::pair<std::int64_t, Box>> cells;
  std::vector<Box> below, boxes;  // the boxes of the level below, and of this one
  for (std::size_t l = 0; l < level_nodes.size(); ++l) {
    const std::uint64_t children = l == 0 ? rows : below.size();
    boxes.clear();
    for (std::uint64_t n = 0; n < level_nodes[l]; ++n) {
      const std::int64_t nodeno = first_node[l] + static_cast<std::int64_t>(n);
      cells.clear();
      Box all;
      for (std::uint64_t c = n * fanout; c < std::min(children, (n + 1) * fanout); ++c) {
        if (l == 0) {
          const Envelope e = envelope(c);
          cells.emplace_back(static_cast<std::int64_t>(c + 1),
                             Box{down(e.min_x), up(e.max_x), down(e.min_y), up(e.max_y)});
        } else {
          const std::int64_t child = first_node[l - 1] + static_cast<std::int64_t>(c);
          cells.emplace_back(child, below[c]);
          parents.append(parents.empty() ? insert_parent : ",").append("(");
          parents.append(std::to_string(child)).append(",").append(std::to_string(nodeno));
          parents.append(")");
          if (parents.size() > (1 << 16)) {
            if (!run(ds, parents)) return false;
            parents.clear();
          }
        }
        all.add(cells.back().second);
      }
      if (!nodes.add(nodeno, depth, cells)) return false;
      boxes.push_back(all);
    }
    std::swap(below, boxes);
  }
  if (!nodes.flush() || (!parents.empty() && !run(ds, parents))) return false;
  // Row k + 1 is in leaf k / fanout.
  if (!run(ds, "INSERT INTO \"" + rtree + "_rowid\" SELECT \"" + fid + "\", " +
                   std::to_string(first_node[0]) + " + (\"" + fid + "\" - 1) / " +
                   std::to_string(fanout) + " FROM \"" + table + "\""))
    return false;
  for (const std::string& sql : triggers(table, column, rtree, fid))
    if (!run(ds, sql)) return false;
  // The extensions table as the specification defines it (a GeoPackage may not have one yet).
  if (!run(ds,
           "CREATE TABLE IF NOT EXISTS gpkg_extensions (table_name TEXT, column_name TEXT, "
           "extension_name TEXT NOT NULL, definition TEXT NOT NULL, scope TEXT NOT NULL, "
           "CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name))"))
    return false;
  return run(ds,
             "INSERT INTO gpkg_extensions (table_name, column_name, extension_name, definition, "
             "scope) VALUES ('" +
                 table + "', '" + column +
                 "', 'gpkg_rtree_index', 'http://www.geopackage.org/spec120/#extension_rtree', "
                 "'write-only')");
}

}  // namespace

bool write_gpkg_rtree(GDALDataset& ds, const std::string& table, const std::string& column,
                      std::uint64_t rows, const std::function<Envelope(std::uint64_t)>& envelope) {
  OGRLayer* layer = ds.GetLayerByName(table.c_str());
  if (layer == nullptr) return false;
  const std::string fid = layer->GetFIDColumn();
  const std::vector<std::int64_t> span = first_row(
      ds, "SELECT min(\"" + fid + "\"), max(\"" + fid + "\"), count(*) FROM \"" + table + "\"");
  if (span.size() != 3) return false;
  // The caller wrote ROWS features into a new table; SQLite numbered them 1, 2, ...
  const auto n = static_cast<std::int64_t>(rows);
  if (span[2] != n || (n > 0 && (span[0] != 1 || span[1] != n)))
    throw InternalError("the GeoPackage table " + table + " holds rows other than fid 1.." +
                        signed_count_text(n));
  if (ds.StartTransaction(FALSE) != OGRERR_NONE) return false;
  if (!pack(ds, table, column, fid, rows, envelope)) {
    ds.RollbackTransaction();
    return false;
  }
  return ds.CommitTransaction() == OGRERR_NONE;
}

}  // namespace tincdt::io::detail
