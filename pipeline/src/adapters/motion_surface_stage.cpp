#include "adapters.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/sampling/motion_surface_sampler.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class MotionSurfaceStage : public Stage {
 public:
  void declare(OptionSet& o) override { o.bind(p_); }
  void prepare() override { p_.validate(); }
  DataFlow flow() const override { return {0u, kPoints | kNormals}; }

  void run(PointData& data, RunContext& context) override {
    MotionSurfaceParameters p = p_;
    p.seed = context.seed;
    Eigen::Matrix3Xd x, n;
    sampleMotionSurface(p, x, n);
    data = sampledPointData(x, n);
    context.report << "sampled " << kMotionSurfaceNames[static_cast<std::size_t>(p.surface)].second
                   << ": " << data.size() << " points\n";
  }

 private:
  MotionSurfaceParameters p_;
};

}  // namespace

StageInfo motionSurfaceSamplingInfo() {
  return {"surface_sampling",
          "seeded points with normals on a surface with one slippable motion: a surface of "
          "revolution, an extrusion or a helicoid",
          [] { return std::unique_ptr<Stage>(new MotionSurfaceStage); }};
}

}  // namespace slipfit::pipeline::adapters
