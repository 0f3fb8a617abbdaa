#include "adapters.h"

#include "slipfit/neighborhoods/grid_search.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/pipeline/errors.h"

#include <array>
#include <memory>
#include <ostream>
#include <string_view>

namespace slipfit::pipeline::adapters {

namespace {

enum class SearchStructure { automatic, kdtree, grid };
constexpr std::array<std::pair<SearchStructure, std::string_view>, 3> kSearchStructureNames{{
    {SearchStructure::automatic, "auto"},
    {SearchStructure::kdtree, "kdtree"},
    {SearchStructure::grid, "grid"},
}};

class NeighborhoodSelectionStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_);
    o.add(
        "search", search_, kSearchStructureNames,
        "How neighbors are found: kdtree (a kd-tree, any cloud); grid (the sensor's pixel grid "
        "of an organized input, as PCL's OrganizedNeighbor: no tree, and a depth "
        "discontinuity separates); auto: the grid when the input is organized, else the kd-tree.");
    o.add("write_fields", write_fields_,
          "Add the per-point fields 'neighbors' (list size) and 'scale' (neighborhood radius) to "
          "the output cloud.");
  }

  void prepare() override { p_.validate(); }
  DataFlow flow() const override { return {kPoints, kNeighborhoods}; }

  void run(PointData& data, RunContext& context) override {
    NeighborhoodParameters p = p_;
    p.threads = context.threads;
    NeighborhoodSelection<pcl::PointNormal> selection;
    selection.setParameters(p);
    selection.setInputCloud(data.cloud);
    const bool organized = !data.pixels.empty() && data.sensor;
    if (search_ == SearchStructure::grid && !organized)
      throw RunError(
          "neighborhood_selection: search = grid needs an organized input (an organized PCD or "
          "a scan_sampling scan, not subsampled); this one has no pixel grid");
    if (search_ != SearchStructure::kdtree && organized)
      selection.setSearchMethod(std::make_shared<GridSearch<pcl::PointNormal>>(
          PixelGrid{data.sensor->width, data.sensor->height, data.pixels}));
    auto hoods = std::make_shared<Neighborhoods>();
    selection.compute(*hoods);
    const auto& st = selection.statistics();
    context.report << "neighborhoods: " << st.queries << " points, sizes " << st.min_size << ".."
                   << st.max_size << " (mean " << st.mean_size << "), ";
    if (st.pixel_grid)
      context.report << "found on the " << data.sensor->width << " x " << data.sensor->height
                     << " pixel grid\n";
    else
      context.report << st.tree_builds << " kd-tree build\n";
    if (st.quantized_axis >= 0)
      context.report << "neighborhoods: " << st.quantized_name << " is recorded on levels "
                     << st.min_step << ".." << st.max_step << " apart; " << st.widened
                     << " neighborhoods widened to span them\n";
    if (st.noise_widened > 0)
      context.report << "neighborhoods: " << st.noise_widened
                     << " widened to span the noise across the surface (local σ "
                     << st.noise_sigma_low << ".." << st.noise_sigma_high
                     << ", 5th to 95th percentile)\n";
    if (write_fields_) {
      const std::size_t n = data.size();
      std::vector<std::int32_t> sizes(n);
      std::vector<float> scale(n);
      for (std::size_t i = 0; i < n; ++i) {
        sizes[i] = static_cast<std::int32_t>((*hoods)[i].size());
        scale[i] = hoods->radius(i);
      }
      data.setField({"neighbors", std::move(sizes)});
      data.setField({"scale", std::move(scale)});
    }
    data.neighborhoods = std::move(hoods);
  }

 private:
  NeighborhoodParameters p_;
  bool write_fields_ = true;
  // The kd-tree by default for now: with the grid, the milk-carton scan's table moved from 0.121°
  // to 0.125° from PCL's RANSAC plane, past RealScanCli's bound (docs/THEORY.md §1).
  SearchStructure search_ = SearchStructure::kdtree;
};

}  // namespace

StageInfo neighborhoodSelectionInfo() {
  return {"neighborhood_selection",
          "kNN, radius, hybrid or adaptive (eigen-entropy) neighborhoods, computed once and shared "
          "by later stages",
          [] { return std::unique_ptr<Stage>(new NeighborhoodSelectionStage); }};
}

}  // namespace slipfit::pipeline::adapters
