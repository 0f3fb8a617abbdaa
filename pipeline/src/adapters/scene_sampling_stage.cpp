#include "adapters.h"

#include "slipfit/scene_sampler.h"

#include <limits>
#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class SceneSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("points", points_, "Surface samples (outliers come on top).")
        .unit("points")
        .range(100, 1e9);
    o.add("noise", p_.noise,
          "σ of Gaussian position noise as a fraction of the object size (the box is 0.8 wide).")
        .range(0, 0.1);
    o.add("outliers", p_.outlier_fraction,
          "Outliers per surface sample, uniform in the scene's box (truth_label -1).")
        .range(0, 1);
    o.add("normals", normals_,
          "Keep the exact normals (false: points only, as a scanner would deliver them).");
  }

  void prepare() override {
    p_.points = static_cast<std::size_t>(points_);
    p_.validate();
  }

  DataFlow flow() const override { return {0u, normals_ ? (kPoints | kNormals) : kPoints}; }

  void run(PointData& data, RunContext& context) override {
    SceneSamplingParameters p = p_;
    p.seed = context.seed;
    Eigen::Matrix3Xd x, n;
    std::vector<std::int32_t> labels;
    sampleScene(p, x, n, labels);
    PointData out;
    out.cloud->resize(static_cast<std::size_t>(x.cols()));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      auto& q = (*out.cloud)[static_cast<std::size_t>(i)];
      q.getVector3fMap() = x.col(i).cast<float>();
      if (normals_)
        q.getNormalVector3fMap() = n.col(i).cast<float>();
      else
        q.getNormalVector3fMap().setConstant(std::numeric_limits<float>::quiet_NaN());
      q.curvature = 0.0f;
    }
    out.has_normals = normals_;
    out.setField({"truth_label", std::move(labels)});
    data = std::move(out);
    context.report << "sampled scene: " << data.size() << " points, " << scenePrimitives().size()
                   << " true primitives\n";
  }

 private:
  SceneSamplingParameters p_;
  int points_ = 100000;
  bool normals_ = true;
};

}  // namespace

StageInfo sceneSamplingInfo() {
  return {"scene_sampling",
          "a labelled test scene (box, cylinder, sphere and cone on a ground plane) with exact "
          "normals and the true label per point (field truth_label)",
          [] { return std::unique_ptr<Stage>(new SceneSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
