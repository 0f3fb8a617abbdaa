#include "adapters.h"

#include "slipfit/random_scene_sampler.h"
#include "slipfit/scene_sampler.h"

#include <array>
#include <string_view>

#include <limits>
#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

enum class Layout { fixed, random };
constexpr std::array<std::pair<Layout, std::string_view>, 2> kLayoutNames{{
    {Layout::fixed, "fixed"},
    {Layout::random, "random"},
}};

class SceneSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("layout", layout_, kLayoutNames,
          "fixed: a box, cylinder, sphere and cone on a ground plane (10 primitives); random: "
          "`shapes` shapes of all five types, sizes over 20×, random poses, touching and "
          "cutting shapes, filleted L-brackets, 500–50,000 points each.");
    o.add("shapes", shapes_, "Random layout: number of primitives.").range(1, 10000);
    o.add("size", random_.size,
          "Random layout: the smallest shape size (the largest is 20 times it).")
        .unit("units")
        .above(0);
    o.add("points", points_, "Surface samples (outliers come on top).")
        .unit("points")
        .range(100, 1e9);
    o.add("noise", p_.noise,
          "σ of Gaussian position noise as a fraction of the object size (fixed: the box is 0.8 "
          "wide; random: the median shape size, at most 0.05).")
        .range(0, 0.1);
    o.add("outliers", p_.outlier_fraction,
          "Outliers per surface sample, uniform in the scene's box (truth_label -1).")
        .range(0, 1);
    o.add("normals", normals_,
          "Keep the exact normals (false: points only, as a scanner would deliver them).");
  }

  void prepare() override {
    p_.points = static_cast<std::size_t>(points_);
    if (layout_ == Layout::fixed) {
      p_.validate();
      return;
    }
    random_.points = p_.points;
    random_.shapes = static_cast<std::size_t>(shapes_);
    random_.noise = p_.noise;
    random_.outlier_fraction = p_.outlier_fraction;
    random_.validate();
  }

  DataFlow flow() const override { return {0u, normals_ ? (kPoints | kNormals) : kPoints}; }

  void run(PointData& data, RunContext& context) override {
    Eigen::Matrix3Xd x, n;
    std::vector<std::int32_t> labels;
    std::vector<Primitive> truth;
    if (layout_ == Layout::fixed) {
      SceneSamplingParameters p = p_;
      p.seed = context.seed;
      sampleScene(p, x, n, labels);
      for (const auto& s : scenePrimitives())
        truth.push_back(s.primitive);
    } else {
      RandomSceneParameters p = random_;
      p.seed = context.seed;
      sampleRandomScene(p, x, n, labels, truth);
    }
    std::vector<std::int32_t> types(labels.size(), -1);
    for (std::size_t i = 0; i < labels.size(); ++i)
      if (labels[i] >= 0)
        types[i] = static_cast<std::int32_t>(truth[static_cast<std::size_t>(labels[i])].index());
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
    out.setField({"truth_type", std::move(types)});
    data = std::move(out);
    context.report << "sampled scene: " << data.size() << " points, " << truth.size()
                   << " true primitives\n";
  }

 private:
  SceneSamplingParameters p_;
  RandomSceneParameters random_;
  Layout layout_ = Layout::fixed;
  int shapes_ = 75;
  int points_ = 100000;
  bool normals_ = true;
};

}  // namespace

StageInfo sceneSamplingInfo() {
  return {"scene_sampling",
          "a labelled test scene (fixed: box, cylinder, sphere and cone on a ground plane; random: "
          "many shapes of all five types) with exact normals and the true label and type per "
          "point (fields truth_label, truth_type)",
          [] { return std::unique_ptr<Stage>(new SceneSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
