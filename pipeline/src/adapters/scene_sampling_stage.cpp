#include "adapters.h"

#include "slipfit/sampling/labelled_scene.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class SceneSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_);
    o.add("normals", normals_,
          "Keep the exact normals (false: points only, as a scanner would deliver them).");
  }

  void prepare() override { p_.validate(); }

  DataFlow flow() const override { return {0u, normals_ ? (kPoints | kNormals) : kPoints}; }

  void run(PointData& data, RunContext& context) override {
    LabelledSceneParameters p = p_;
    p.seed = context.seed;
    LabelledScene scene = sampleLabelledScene(p);
    PointData out = sampledPointData(scene.points, scene.normals, normals_);
    out.setField({"truth_label", std::move(scene.labels)});
    out.setField({"truth_type", std::move(scene.types)});
    data = std::move(out);
    context.report << "sampled scene: " << data.size() << " points, " << scene.truth.size()
                   << " true surfaces\n";
  }

 private:
  LabelledSceneParameters p_;
  bool normals_ = true;
};

}  // namespace

StageInfo sceneSamplingInfo() {
  return {"scene_sampling",
          "a labelled test scene (fixed: box, cylinder, sphere and cone on a ground plane; random: "
          "many shapes of all five types; kinematic: a turned part, an extruded section and a "
          "threaded rod among primitives) with exact normals and the true label and type per "
          "point (fields truth_label, truth_type)",
          [] { return std::unique_ptr<Stage>(new SceneSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
