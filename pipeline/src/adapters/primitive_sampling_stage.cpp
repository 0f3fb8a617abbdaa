#include "adapters.h"

#include "slipfit/angle_units.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/primitive_sampler.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class PrimitiveSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("shape", type_, kPrimitiveTypeNames, "Primitive to sample.");
    o.add("normal", normal_, "Plane: normal n (normalised) of n·x = d.");
    o.add("d", d_, "Plane: offset d of n·x = d.").unit("units");
    o.add("center", center_, "Sphere, torus: centre.").unit("units");
    o.add("radius", radius_, "Sphere, cylinder: radius.").unit("units").above(0);
    o.add("axis", axis_,
          "Cylinder, cone, torus: axis direction (cone: from the apex into the opening).");
    o.add("point", point_, "Cylinder: a point on the axis; heights are measured from it.")
        .unit("units");
    o.add("apex", apex_, "Cone: apex.").unit("units");
    o.add("half_angle", half_angle_, "Cone: half opening angle.").unit("deg").range(0.01, 89.99);
    o.add("major_radius", major_radius_, "Torus: radius R of the circle of tube centres.")
        .unit("units")
        .above(0);
    o.add("minor_radius", minor_radius_, "Torus: tube radius r (0 < r < R).")
        .unit("units")
        .above(0);
    o.add("extent", p_.extent,
          "Plane: half side of the square; cylinder: largest height; cone: largest axial distance "
          "from the apex.")
        .unit("units")
        .above(0);
    o.add("extent_min", p_.extent_min,
          "Cylinder: smallest height; cone: smallest axial distance (a band away from the apex).")
        .unit("units")
        .atLeast(0);
    o.add("angle_min", angle_min_, "Cylinder, cone, torus: coverage around the axis starts here.")
        .unit("deg")
        .atLeast(0)
        .below(360);
    o.add("angle_max", angle_max_,
          "Cylinder, cone, torus: coverage around the axis ends here (above angle_min).")
        .unit("deg")
        .above(0)
        .atMost(360);
    o.add("cap", cap_,
          "Sphere: half angle of the spherical cap around cap_axis (180: whole sphere).")
        .unit("deg")
        .range(0.01, 180);
    o.add("cap_axis", cap_axis_, "Sphere: direction of the cap's centre.");
    o.add("points", points_, "Surface samples (outliers come on top).")
        .unit("points")
        .range(1, 1e9);
    o.add("noise", p_.noise, "σ of Gaussian noise added to each coordinate.")
        .unit("units")
        .atLeast(0);
    o.add("normal_noise", normal_noise_, "σ of the perturbation of the normals.")
        .unit("deg")
        .atLeast(0);
    o.add("outliers", p_.outlier_fraction,
          "Outliers per surface sample, uniform in the samples' box; field 'outlier'.")
        .range(0, 1);
    o.add("flips", p_.flip_fraction, "Fraction of normals with flipped sign.").range(0, 1);
  }

  void prepare() override {
    switch (type_) {
      case PrimitiveType::plane:
        p_.primitive = Plane{normal_.cast<double>().normalized(), d_};
        break;
      case PrimitiveType::sphere:
        p_.primitive = Sphere{center_.cast<double>(), radius_};
        break;
      case PrimitiveType::cylinder:
        p_.primitive = Cylinder{axis_.cast<double>().normalized(), point_.cast<double>(), radius_};
        break;
      case PrimitiveType::cone:
        p_.primitive =
            Cone{axis_.cast<double>().normalized(), apex_.cast<double>(), half_angle_ * kDegree};
        break;
      case PrimitiveType::torus:
        p_.primitive = Torus{axis_.cast<double>().normalized(), center_.cast<double>(),
                             major_radius_, minor_radius_};
        break;
    }
    p_.points = static_cast<std::size_t>(points_);
    p_.angle_min = angle_min_ * kDegree;
    p_.angle_max = angle_max_ * kDegree;
    p_.cap = cap_ * kDegree;
    p_.axis_hint = cap_axis_.cast<double>();
    p_.normal_noise = normal_noise_ * kDegree;
    p_.validate();
  }

  DataFlow flow() const override { return {0u, kPoints | kNormals}; }

  void run(PointData& data, RunContext& context) override {
    PrimitiveSamplingParameters p = p_;
    p.seed = context.seed;
    Eigen::Matrix3Xd x, n;
    std::vector<std::int32_t> outlier;
    samplePrimitive(p, x, n, &outlier);
    PointData out;
    out.cloud->resize(static_cast<std::size_t>(x.cols()));
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      auto& q = (*out.cloud)[static_cast<std::size_t>(i)];
      q.getVector3fMap() = x.col(i).cast<float>();
      q.getNormalVector3fMap() = n.col(i).cast<float>();
      q.curvature = 0.0f;
    }
    out.has_normals = true;
    out.setField({"outlier", std::move(outlier)});
    data = std::move(out);
    context.report << "sampled " << primitiveTypeName(type_) << ": " << data.size() << " points\n";
  }

 private:
  PrimitiveSamplingParameters p_;
  PrimitiveType type_ = PrimitiveType::plane;
  Eigen::Vector3f normal_ = Eigen::Vector3f::UnitZ(), center_ = Eigen::Vector3f::Zero(),
                  axis_ = Eigen::Vector3f::UnitZ(), point_ = Eigen::Vector3f::Zero(),
                  apex_ = Eigen::Vector3f::Zero(), cap_axis_ = Eigen::Vector3f::UnitZ();
  double d_ = 0.0, radius_ = 1.0, half_angle_ = 30.0, major_radius_ = 1.0, minor_radius_ = 0.25;
  double angle_min_ = 0.0, angle_max_ = 360.0, cap_ = 180.0, normal_noise_ = 0.0;
  int points_ = 10000;
};

}  // namespace

StageInfo primitiveSamplingInfo() {
  return {"primitive_sampling",
          "seeded points with normals on a plane, sphere, cylinder or cone with known parameters "
          "(noise, outliers, partial coverage, normal noise and sign flips)",
          [] { return std::unique_ptr<Stage>(new PrimitiveSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
