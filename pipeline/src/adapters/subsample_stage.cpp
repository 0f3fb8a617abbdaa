#include "adapters.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/subsampling.h"

#include <array>
#include <ostream>
#include <sstream>
#include <string>

namespace slipfit::pipeline::adapters {

namespace {

enum class Mode { random, voxel };
constexpr std::array<std::pair<Mode, std::string_view>, 2> kModeNames{{
    {Mode::random, "random"},
    {Mode::voxel, "voxel"},
}};

enum class Position { mean, first };
constexpr std::array<std::pair<Position, std::string_view>, 2> kPositionNames{{
    {Position::mean, "mean"},
    {Position::first, "first"},
}};

class SubsampleStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("mode", mode_, kModeNames,
          "random: each point kept with probability points / N (seeded; outliers keep their "
          "proportion), represented by a kept point of its grid cell; voxel: one point per voxel "
          "(even "
          "density, but every isolated outlier survives).");
    o.add("points", points_,
          "Keep about this many points, one per voxel (the leaf is found in a few passes).")
        .unit("points")
        .range(100, 1e9);
    o.add("leaf", leaf_, "Voxel mode: voxel edge; overrides points.").unit("units").above(0);
    o.add("position", position_, kPositionNames,
          "Voxel mode: where the analysis point lies. mean: at the centroid of its voxel's points "
          "(as PCL's VoxelGrid): their noise averages down, so normals and fits on dense surfaces "
          "see more than one sample's scatter; first: at the voxel's first input point.");
  }

  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    if (data.full)
      throw RunError("the cloud is already subsampled");
    const auto n = static_cast<Eigen::Index>(data.size());
    Eigen::Matrix3Xf x(3, n);
    for (Eigen::Index i = 0; i < n; ++i)
      x.col(i) = (*data.cloud)[static_cast<std::size_t>(i)].getVector3fMap();
    const auto target = static_cast<std::size_t>(points_);
    const Subsample s = mode_ == Mode::random
                            ? randomSample(x, target, context.seed)
                            : (leaf_ ? voxelSample(x, *leaf_) : voxelSampleTo(x, target));
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
    std::string placed;
    if (mode_ == Mode::voxel && position_ == Position::mean) {
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
                   << (mode_ == Mode::random ? std::string("random")
                                             : "voxel " + std::to_string(s.leaf) + placed)
                   << "); results are carried back to every point\n";
  }

 private:
  Mode mode_ = Mode::random;
  int points_ = 150000;
  std::optional<double> leaf_;
  Position position_ = Position::mean;
};

}  // namespace

StageInfo subsampleInfo() {
  return {"subsample",
          "one point per voxel for the analysis stages that follow; their results (normals, "
          "fields, segments) are carried back to every input point at the end",
          [] { return std::unique_ptr<Stage>(new SubsampleStage); }};
}

}  // namespace slipfit::pipeline::adapters
