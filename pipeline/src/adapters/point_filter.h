#pragma once
/// \file What the filter stages (crop, voxel_grid, outlier_removal) share: each wraps a PCL filter
/// that selects points, runs on the input cloud (before a subsample stage) and keeps the points it
/// selects, in their order, with every field; the others are absent from every output.

#include "slipfit/pipeline/point_data.h"
#include "slipfit/pipeline/stage.h"
#include "slipfit/point_filters.h"

#include <string>

namespace slipfit::pipeline::adapters {

/// Throws RunError when \a data is an analysis sample: a filter decides which input points exist,
/// so it comes before the subsample stage.
void requireInputCloud(const PointData& data);

/// Keeps the points a filter selected (slipfit/point_filters.h) and reports
/// "<name>: <kept> of <n> points kept, <dropped> dropped (<why>)". Throws RunError when none is
/// kept.
void keepFiltered(PointData& data, const FilterSelection& selection, RunContext& context,
                  const std::string& name);

}  // namespace slipfit::pipeline::adapters
