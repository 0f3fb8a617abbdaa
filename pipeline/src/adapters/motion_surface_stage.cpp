#include "adapters.h"

#include "slipfit/motion_surface_sampler.h"
#include "slipfit/pipeline/errors.h"

#include <Eigen/Geometry>

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class MotionSurfaceStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("shape", p_.surface, kMotionSurfaceNames,
          "revolution: a vase ρ(t) = radius (1 + 0.3 sin(2π t / length)); extrusion: an ellipse "
          "(radius, radius / 2) swept along the axis; helix: the helicoid (r cos θ, r sin θ, pitch "
          "θ).");
    o.add("radius", p_.radius, "Size across the axis.").unit("units").above(0);
    o.add("length", p_.length, "Extent along the axis.").unit("units").above(0);
    o.add("pitch", p_.pitch, "Helix: rise per radian (non-zero).").unit("units/rad");
    o.add("center", center_, "Where the surface's axis starts.").unit("units");
    o.add("axis", axis_, "Direction of the axis (normalised).");
    o.add("points", points_, "Samples.").unit("points").range(1, 1e9);
    o.add("noise", p_.noise, "σ of Gaussian noise added to each coordinate.")
        .unit("units")
        .atLeast(0);
  }
  void prepare() override {
    p_.points = static_cast<std::size_t>(points_);
    if (!(axis_.norm() > 0.0f))
      throw OptionValueError("axis must be non-zero");
    p_.validate();
  }
  DataFlow flow() const override { return {0u, kPoints | kNormals}; }

  void run(PointData& data, RunContext& context) override {
    MotionSurfaceParameters p = p_;
    p.seed = context.seed;
    Eigen::Matrix3Xd x, n;
    sampleMotionSurface(p, x, n);
    const Eigen::Matrix3d rotation =
        Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(),
                                           axis_.cast<double>().normalized())
            .toRotationMatrix();
    PointData out;
    out.cloud->resize(static_cast<std::size_t>(x.cols()));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      auto& q = (*out.cloud)[static_cast<std::size_t>(i)];
      q.getVector3fMap() = (rotation * x.col(i) + center_.cast<double>()).cast<float>();
      q.getNormalVector3fMap() = (rotation * n.col(i)).cast<float>();
      q.curvature = 0.0f;
    }
    out.has_normals = true;
    data = std::move(out);
    context.report << "sampled " << kMotionSurfaceNames[static_cast<std::size_t>(p.surface)].second
                   << ": " << data.size() << " points\n";
  }

 private:
  MotionSurfaceParameters p_;
  Eigen::Vector3f center_ = Eigen::Vector3f::Zero(), axis_ = Eigen::Vector3f::UnitZ();
  int points_ = 5000;
};

}  // namespace

StageInfo motionSurfaceSamplingInfo() {
  return {"surface_sampling",
          "seeded points with normals on a surface with one slippable motion: a surface of "
          "revolution, an extrusion or a helicoid",
          [] { return std::unique_ptr<Stage>(new MotionSurfaceStage); }};
}

}  // namespace slipfit::pipeline::adapters
