#pragma once
/// \file What the filter stages (crop, voxel_grid, outlier_removal) share: each wraps a PCL filter
/// that selects points, runs on the input cloud (before a subsample stage) and keeps the points it
/// selects, in their order, with every field; the others are absent from every output.

#include "slipfit/filters/point_filters.h"
#include "slipfit/pipeline/point_data.h"
#include "slipfit/pipeline/stage.h"

#include <string>
#include <utility>
#include <vector>

namespace slipfit::pipeline::adapters {

/// Throws RunError when \a data is an analysis sample: a filter decides which input points exist,
/// so it comes before the subsample stage.
void requireInputCloud(const PointData& data);

/// Keeps the points a filter selected (slipfit/filters/point_filters.h) and reports
/// "<name>: <kept> of <n> points kept, <dropped> dropped (<why>)". Throws RunError when none is
/// kept.
void keepFiltered(PointData& data, const FilterSelection& selection, RunContext& context,
                  const std::string& name);

/// A stage that runs one filter of slipfit/filters/point_filters.h on the input cloud: its options
/// are the filter's Parameters, and `select` runs the filter on the cloud (positions, when not
/// empty: where the kept points move, in order).
template <typename Parameters>
class FilterStage : public Stage {
 public:
  using Select = FilterSelection (*)(const PointData& data, const Parameters& parameters,
                                     std::vector<Eigen::Vector3f>& positions);
  FilterStage(std::string name, Select select) : name_(std::move(name)), select_(select) {}

  void declare(OptionSet& o) override { o.bind(parameters_); }
  void prepare() override { parameters_.validate(); }
  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    std::vector<Eigen::Vector3f> positions;
    keepFiltered(data, select_(data, parameters_, positions), context, name_);
    for (std::size_t k = 0; k < positions.size(); ++k)
      (*data.cloud)[k].getVector3fMap() = positions[k];
  }

 private:
  Parameters parameters_;
  std::string name_;
  Select select_;
};

}  // namespace slipfit::pipeline::adapters
