// The DEM's grid checked as soon as the inputs are read, before any triangle is made.
#pragma once

#include "pipeline/job.hpp"

namespace tincdt::pipeline {

// Refuses (OutputError) the DEM of JOB's options when its grid over the points' extent (or
// --dem-extent) is too fine for the coordinates, has fewer than 2 x 2 cells or would not fit in
// memory; nothing without a DEM or with a grid fixed by the caller (Job::dem_grid).
void check_dem_grid_early(const Job& job);

}  // namespace tincdt::pipeline
