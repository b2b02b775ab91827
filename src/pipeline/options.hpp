// The settings of a job, one field per setting, grouped in the order of the stages they
// configure. apps/tincdt binds its command line to these fields.
#pragma once

#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/points/point_reader.hpp"
#include "io/vector/line_reader.hpp"

namespace tincdt::pipeline {

// One field per job setting, grouped by stage. Later stages (contours / breaklines from OGR
// sources, restoration mode, clipping) add their own fields next to the stage they configure.
struct BuildOptions {
  // ---- input ---------------------------------------------------------------------------
  std::vector<std::string> inputs;  // point files (LAS, XYZ, "-")
  io::PointFilter filter;
  std::string assign_crs_wkt;  // --a-srs: the inputs' CRS, replacing any in the files

  // Contours and hard lines (any OGR source, "FILE" or "FILE:LAYER"): their vertices join the
  // Delaunay stage, their segments become constrained edges. Lines alone make a valid job.
  // Contour vertices are the ones --fix-flats looks at; breaklines (--breaklines, --hard-lines)
  // are otherwise the same.
  std::vector<std::string> contours;
  std::vector<std::string> breaklines;
  io::LineReadOptions lines;  // --layer, --z-field, --z-from-m, for every vector source

  // ---- surface features (any OGR source, "FILE" or "FILE:LAYER"; lines.layer applies) -------
  // Inserted after the TIN of points and hard lines is built and constrained. Their 2D vertices
  // are draped: z from that TIN (linear interpolation); a vertex outside it is an InputError
  // naming the feature. Then their segments become constrained edges; where one crosses a hard
  // line or contour, the new vertex takes the hard line's z.
  std::vector<std::string> soft_lines;  // lines, always draped (a z of their own is ignored)
  std::vector<std::string> clip;        // polygons: triangles outside all of them are removed
  std::vector<std::string> erase;       // polygons: triangles inside any of them are removed
  std::vector<std::string> replace;     // polygons: vertices on or inside get the polygon's z
                                        // (lines.z_field, else lines.z_from_m, else 3D z)
  // Clip and erase rings with a z of their own (3D geometry) keep it; 2D rings are draped.

  // ---- TIN boundary and quality, applied in this order -----------------------------------
  //   fix flats -> replace -> trim (max_edge) -> clip -> erase
  // Flats are fixed on the whole TIN before any z is replaced (a replace polygon makes flat
  // triangles on purpose) and before any triangle is removed (fix_flat_triangles needs the
  // whole TIN). Trimming works inward from the convex hull only, before clip and erase open
  // new boundaries. Where clip and erase overlap, erase wins; vertices of a replace polygon
  // inside an erase polygon are replaced, but their triangles are removed.
  bool fix_flats = false;  // --fix-flats: needs contours (their vertices define the flats)
  double max_edge = 0;     // --max-edge LENGTH: > 0 trims boundary triangles; 0 = no trimming

  // ---- Delaunay stage --------------------------------------------------------------------
  delaunay::DuplicatePolicy on_duplicate = delaunay::DuplicatePolicy::mean;
  bool validate = false;  // run Triangulation::validate() before writing (slow)

  // ---- constraint stage ------------------------------------------------------------------
  constraints::ConstraintOptions constraint;  // --restore, --on-crossing

  // ---- output --------------------------------------------------------------------------
  std::string output;
  io::TinWriteOptions write;  // format, ply_ascii, overwrite, offset, target CRS
                              // (write.crs_wkt is filled by build() from the inputs)
  bool offset_auto = false;   // write.offset = data's min corner rounded down to 1000
  std::string stats_path;     // --stats FILE.json, empty = none; honours write.overwrite
  // --constraints-out FILE.geojson: every constrained edge of the written TIN with its source
  // feature (as the TIN: write.offset, write.target_crs_wkt, overwrite, temporary + rename).
  std::string constraints_out;
  // --diagnostics FILE.gpkg: crossings, skipped segments and dropped features as GIS layers.
  std::string diagnostics;
};

}  // namespace tincdt::pipeline
