#include "adapters.h"

#include "slipfit/core/cloud_maps.h"

#include "slipfit/filters/subsampling.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/tile_roles.h"

#include <ostream>
#include <sstream>
#include <string>

namespace slipfit::pipeline::adapters {

namespace {

class SubsampleStage : public Stage, public SampledAnalysis {
 public:
  void declare(OptionSet& o) override { o.bind(p_); }
  void prepare() override { p_.validate(); }

  const SubsampleParameters& sampling() const override { return p_; }
  void setSampling(const SubsampleParameters& sampling) override {
    sampling.validate();
    p_ = sampling;
  }

  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    if (data.full)
      throw RunError("the cloud is already subsampled");
    const Eigen::Matrix3Xf x = coordinates(*data.cloud);  // the cloud is replaced below
    SubsampleParameters p = p_;
    if (p.origin)
      *p.origin -= data.frame.shift;  // given in the input's frame
    const Subsample s = subsample(x, p, context.seed);
    if (s.kept.size() == data.size()) {
      context.report << "subsample: " << data.size() << " points, none dropped\n";
      return;
    }
    auto full = std::make_shared<PointData>(data);  // shares the cloud: keepOnly replaces ours
    full->neighborhoods.reset();
    std::vector<char> keep(data.size(), 0);
    for (std::int32_t k : s.kept)
      keep[static_cast<std::size_t>(k)] = 1;
    data.keepOnly(keep);
    data.pixels.clear();  // the analysis points stand for voxels, not pixels
    std::string placed;
    const VoxelPlacement placement = p_.mode == SubsampleMode::voxel
                                         ? voxelPlacement(x, p_.position)
                                         : VoxelPlacement{SubsamplePosition::first, -1, {}};
    if (placement.levels_axis >= 0)
      placed = ", at each voxel's first point: " + placement.levels_name +
               " is recorded on levels, which the mean of a voxel's points would leave";
    if (placement.position == SubsamplePosition::mean) {
      RepresentedMean mean = representedMean(x, s);
      std::size_t averaged = 0;
      for (std::size_t k = 0; k < s.kept.size(); ++k) {
        (*data.cloud)[k].getVector3fMap() = mean.mean.col(static_cast<Eigen::Index>(k));
        averaged += mean.count[k];
      }
      data.averaged = true;
      std::ostringstream text;
      text << ", at the mean of " << static_cast<double>(averaged) / double(s.kept.size())
           << " points on average";
      placed = text.str();
    }
    data.full = std::move(full);
    data.representative = s.representative;
    context.report << "subsample: " << data.size() << " of " << data.full->size()
                   << " points analysed ("
                   << (p_.mode == SubsampleMode::random
                           ? std::string("random")
                           : "voxel " + std::to_string(s.leaf) + placed)
                   << "); results are carried back to every point\n";
  }

 private:
  SubsampleParameters p_;
};

}  // namespace

StageInfo subsampleInfo() {
  return {"subsample",
          "one point per voxel for the analysis stages that follow; their results (normals, "
          "fields, segments) are carried back to every input point at the end",
          [] { return std::unique_ptr<Stage>(new SubsampleStage); }};
}

}  // namespace slipfit::pipeline::adapters
