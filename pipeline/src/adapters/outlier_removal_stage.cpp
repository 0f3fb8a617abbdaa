#include "adapters.h"
#include "point_filter.h"

#include "slipfit/point_filters.h"

namespace slipfit::pipeline::adapters {

namespace {

/// PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval.
class OutlierRemovalStage : public Stage {
 public:
  void declare(OptionSet& o) override { o.bind(p_); }
  void prepare() override { p_.validate(); }
  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    keepFiltered(data, removeOutliers(data.cloud, p_), context, "outlier_removal");
  }

 private:
  OutlierRemovalParameters p_;
};

}  // namespace

StageInfo outlierRemovalInfo() {
  return {"outlier_removal",
          "drops isolated points (PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval): they "
          "are absent from every output",
          [] { return std::unique_ptr<Stage>(new OutlierRemovalStage); }};
}

}  // namespace slipfit::pipeline::adapters
