#include "adapters.h"

#include "slipfit/neighborhood_selection.h"
#include "slipfit/pipeline/errors.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class NeighborhoodSelectionStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("mode", p_.mode, kNeighborhoodModeNames,
          "knn: the k nearest points; radius: all points within radius; hybrid: the k nearest "
          "but none beyond radius; adaptive: per point the k in [k_min, k_max] of least "
          "eigen-entropy (Weinmann et al. 2015).");
    o.add("k", p_.k, "Neighbors per point (knn), or the cap (hybrid); includes the point itself.")
        .unit("points")
        .range(3, 10000);
    o.add("radius", p_.radius, "Search radius (radius and hybrid modes).")
        .unit("cloud units")
        .above(0);
    o.add("max_neighbors", p_.max_neighbors,
          "Radius mode: keep at most this many of the nearest (unset: all).")
        .unit("points")
        .range(3, 1e7);
    o.add("k_min", p_.k_min, "Adaptive mode: smallest candidate size.")
        .unit("points")
        .range(3, 10000);
    o.add("k_max", p_.k_max, "Adaptive mode: largest candidate size.")
        .unit("points")
        .range(3, 10000);
    o.add("k_step", p_.k_step, "Adaptive mode: step between candidate sizes.")
        .unit("points")
        .range(1, 1000);
    o.add("span_quantization", p_.span_quantization,
          "knn: where one coordinate is recorded on levels (Kinect-like depth), widen the "
          "neighborhoods that lie within 1.5 local steps to every point within 1.5 steps (at "
          "most 8 k), so that they span the levels.");
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
    auto hoods = std::make_shared<Neighborhoods>();
    selection.compute(*hoods);
    const auto& st = selection.statistics();
    context.report << "neighborhoods: " << st.queries << " points, sizes " << st.min_size << ".."
                   << st.max_size << " (mean " << st.mean_size << "), " << st.tree_builds
                   << " kd-tree build\n";
    if (st.quantized_axis >= 0)
      context.report << "neighborhoods: coordinate "
                     << "xyz"[st.quantized_axis] << " is recorded on levels " << st.min_step << ".."
                     << st.max_step << " apart; " << st.widened
                     << " neighborhoods widened to span them\n";
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
};

}  // namespace

StageInfo neighborhoodSelectionInfo() {
  return {"neighborhood_selection",
          "kNN, radius, hybrid or adaptive (eigen-entropy) neighborhoods, computed once and shared "
          "by later stages",
          [] { return std::unique_ptr<Stage>(new NeighborhoodSelectionStage); }};
}

}  // namespace slipfit::pipeline::adapters
