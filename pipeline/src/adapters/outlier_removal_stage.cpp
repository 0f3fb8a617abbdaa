#include "adapters.h"
#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>

#include <array>
#include <optional>
#include <sstream>
#include <string>

namespace slipfit::pipeline::adapters {

namespace {

enum class Method { statistical, radius };
constexpr std::array<std::pair<Method, std::string_view>, 2> kMethodNames{{
    {Method::statistical, "statistical"},
    {Method::radius, "radius"},
}};

/// PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval.
class OutlierRemovalStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("method", method_, kMethodNames,
          "statistical: drop points whose mean distance to their k nearest neighbors exceeds the "
          "mean over the cloud by more than stddev standard deviations "
          "(StatisticalOutlierRemoval); radius: drop points with fewer than min_neighbors "
          "others within radius (RadiusOutlierRemoval).");
    o.add("k", k_, "statistical: neighbors per point (PCL's tutorial: 50).")
        .unit("points")
        .range(2, 10000);
    o.add("stddev", stddev_, "statistical: the threshold, in standard deviations above the mean.")
        .range(0, 100);
    o.add("radius", radius_, "radius: the search radius.").unit("cloud units").above(0);
    o.add("min_neighbors", min_neighbors_, "radius: the fewest neighbors a kept point has.")
        .unit("points")
        .range(1, 10000);
  }

  void prepare() override {
    if ((method_ == Method::radius) != radius_.has_value())
      throw OptionValueError(method_ == Method::radius ? "method radius needs radius"
                                                       : "radius is for method radius");
  }

  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    pcl::Indices kept;
    std::ostringstream why;
    if (method_ == Method::statistical) {
      pcl::StatisticalOutlierRemoval<pcl::PointNormal> sor;
      sor.setInputCloud(data.cloud);
      sor.setMeanK(k_);
      sor.setStddevMulThresh(stddev_);
      sor.filter(kept);
      why << "mean distance to " << k_ << " neighbors within " << stddev_
          << " standard deviations of the cloud's";
    } else {
      pcl::RadiusOutlierRemoval<pcl::PointNormal> ror;
      ror.setInputCloud(data.cloud);
      ror.setRadiusSearch(*radius_);
      ror.setMinNeighborsInRadius(min_neighbors_);
      ror.filter(kept);
      why << "at least " << min_neighbors_ << " neighbors within " << *radius_;
    }
    keepFiltered(data, kept, context, "outlier_removal", why.str());
  }

 private:
  Method method_ = Method::statistical;
  int k_ = 50;
  double stddev_ = 1.0;
  std::optional<double> radius_;
  int min_neighbors_ = 2;
};

}  // namespace

StageInfo outlierRemovalInfo() {
  return {"outlier_removal",
          "drops isolated points (PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval): they "
          "are absent from every output",
          [] { return std::unique_ptr<Stage>(new OutlierRemovalStage); }};
}

}  // namespace slipfit::pipeline::adapters
