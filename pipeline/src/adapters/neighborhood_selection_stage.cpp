#include "adapters.h"

#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/pipeline/errors.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class NeighborhoodSelectionStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_);
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
