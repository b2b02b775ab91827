// The R-tree spatial index of a GeoPackage feature table (extension gpkg_rtree_index, GeoPackage
// 1.2 annex F.3), packed in one pass instead of grown row by row.
//
// SQLite's rtree module inserts one row at a time, choosing a leaf and splitting nodes as they
// fill: three quarters of the time of writing a TIN to a GeoPackage. When the rows are already in
// spatial order (a TIN's triangles in the order of their vertices' Hilbert curve), consecutive
// rows make good leaves and consecutive nodes good parents, so the tree can be written directly
// into the module's three tables, as SQLite's ext/rtree lays them out:
//   <name>_node(nodeno, data): node 1 is the root; a node is a 2-byte depth (read from the root
//     only: 0 when the root is a leaf), a 2-byte cell count, then cells of a 64-bit id (the row
//     in a leaf, the child node above) and float32 min x, max x, min y, max y, all big-endian,
//     the blob as long as the module made the root (its node size);
//   <name>_rowid(rowid, nodeno): the leaf of each row;  <name>_parent(nodeno, parentnode).
// Boxes are rounded outwards to float32, as the module does. The triggers that keep the index
// in step with later edits, and the gpkg_extensions row, are the specification's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "io/gdal_support.hpp"

namespace tincdt::io::detail {

struct Envelope {
  double min_x, max_x, min_y, max_y;
};

// Creates the spatial index "rtree_<table>_<column>" of TABLE (geometry column COLUMN), whose
// rows must be fid 1..ROWS with the envelope ENVELOPE(i) for fid i + 1, in one transaction of
// DS (none may be open); other rows are an InternalError. False when GDAL or SQLite failed
// (last_gdal_message() says why).
bool write_gpkg_rtree(GDALDataset& ds, const std::string& table, const std::string& column,
                      std::uint64_t rows, const std::function<Envelope(std::uint64_t)>& envelope);

}  // namespace tincdt::io::detail
