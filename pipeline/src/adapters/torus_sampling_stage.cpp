#include "adapters.h"

#include "slipfit/angle_units.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/mesh_io.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/torus_sampler.h"

#include <iomanip>
#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class TorusSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("major_radius", p_.shape.R, "R: radius of the centre circle of the tube.")
        .unit("units")
        .above(0);
    o.add("minor_radius", p_.shape.r, "r: radius of the tube; 0 < r < R.").unit("units").above(0);
    o.add("center", center_, "Position of the torus centre.").unit("units");
    o.add("axis", axis_, "Direction of the symmetry axis (normalised).");
    o.add("spin", spin_,
          "Rotation about the axis: where β = 0 lies (matters for partial coverage).")
        .unit("deg")
        .range(-360, 360);
    o.add("points", points_, "Surface samples (outliers come on top).")
        .unit("points")
        .range(1, 1e9);
    o.add("sampling", p_.sampling, kTorusSamplingNames,
          "area: uniform on the surface (density ∝ R + r cos α); angle: uniform in (α, β); "
          "parameter: uniform in the Bézier quarters' (u, v).");
    o.add("alpha_min", alpha_min_,
          "Coverage around the tube starts here (α = 0: outer equator, 90: top).")
        .unit("deg")
        .atLeast(0)
        .below(360);
    o.add("alpha_max", alpha_max_, "Coverage around the tube ends here (above alpha_min).")
        .unit("deg")
        .above(0)
        .atMost(360);
    o.add("beta_min", beta_min_, "Coverage around the axis starts here (β = 0 on +x).")
        .unit("deg")
        .atLeast(0)
        .below(360);
    o.add("beta_max", beta_max_, "Coverage around the axis ends here (above beta_min).")
        .unit("deg")
        .above(0)
        .atMost(360);
    o.add("noise", p_.noise, "σ of Gaussian noise added to each coordinate.")
        .unit("units")
        .atLeast(0);
    o.add("normal_noise", normal_noise_, "σ of the perturbation of the normals.")
        .unit("deg")
        .atLeast(0);
    o.add("outliers", p_.outlier_fraction,
          "Outliers per surface sample, uniform in the bounding box with random normals; marked "
          "by the field 'outlier'.")
        .range(0, 1);
    o.add("mesh", mesh_, "Also write the stitched quad mesh as OFF (with normals, NOFF) and PLY.");
    o.add("mesh_name", mesh_name_, "Base name of the mesh files in the output dir.").fileName();
    o.add("mesh_alpha", m_.n_alpha, "Mesh vertices around the tube.")
        .unit("vertices")
        .range(3, 100000);
    o.add("mesh_beta", m_.n_beta, "Mesh vertices around the axis.")
        .unit("vertices")
        .range(3, 100000);
    o.add("mesh_spacing", m_.spacing, kTorusSpacingNames,
          "angle: vertices uniform in (α, β); parameter: uniform in the quarters' (u, v) "
          "(even resolutions).");
    o.add("mesh_naive", naive_,
          "Also write <mesh_name>_naive.off: four separate quarter meshes with duplicated seam "
          "vertices and face-averaged normals, to compare with the stitched mesh.");
    o.add("print_sites", print_sites_,
          "Print the 9 homogeneous Bézier sites [w; x, y, z] of each quarter patch.");
  }

  void prepare() override {
    p_.center = center_.cast<double>();
    p_.axis = axis_.cast<double>();
    p_.points = static_cast<std::size_t>(points_);
    p_.spin = spin_ * kDegree;
    p_.alpha_min = alpha_min_ * kDegree;
    p_.alpha_max = alpha_max_ * kDegree;
    p_.beta_min = beta_min_ * kDegree;
    p_.beta_max = beta_max_ * kDegree;
    p_.normal_noise = normal_noise_ * kDegree;
    p_.validate();
    if (mesh_ || naive_)
      m_.validate();
    if (naive_) {
      TorusMeshParameters q = m_;
      q.spacing = TorusSpacing::parameter;
      q.validate();
    }
  }

  DataFlow flow() const override { return {0u, kPoints | kNormals}; }

  std::vector<std::string> outputFiles() const override {
    std::vector<std::string> names;
    if (mesh_)
      names = {mesh_name_ + ".off", mesh_name_ + ".ply"};
    if (naive_)
      names.push_back(mesh_name_ + "_naive.off");
    return names;
  }

  void run(PointData& data, RunContext& context) override {
    TorusSamplingParameters p = p_;
    p.seed = context.seed;
    TorusSampler sampler;
    sampler.setParameters(p);
    PointData out;
    std::vector<std::int32_t> outlier;
    sampler.sample(*out.cloud, &outlier);
    out.has_normals = true;
    out.setField({"outlier", std::move(outlier)});
    data = std::move(out);
    context.report << "torus: R = " << p.shape.R << ", r = " << p.shape.r << ", " << data.size()
                   << " points (" << p.points << " on the surface)\n";

    if (print_sites_) {
      for (int quarter = 0; quarter < 4; ++quarter) {
        context.report << "torus quarter " << quarter << " sites [w; x, y, z]:";
        const RationalBezierPatch patch = torusQuarterPatch(p.shape, quarter);
        for (const auto& site : patch.sites()) {
          const Eigen::Vector4d s = site + Eigen::Vector4d::Zero();  // −0 prints as 0
          context.report << " [" << s[0] << "; " << s[1] << ", " << s[2] << ", " << s[3] << "]";
        }
        context.report << "\n";
      }
    }
    if ((mesh_ || naive_) && !context.outputs)
      throw RunError("no output directory for the mesh");
    if (mesh_) {
      auto mesh = std::make_shared<SurfaceMesh>(torusMesh(p.shape, m_, p.pose()));
      for (const char* ext : {".off", ".ply"})
        context.outputs->add(mesh_name_ + ext,
                             [&](const std::string& path) { writeMesh(*mesh, path, true, false); });
      context.report << "torus mesh: " << mesh->n_vertices() << " vertices, " << mesh->n_faces()
                     << " quads\n";
    }
    if (naive_) {
      const SurfaceMesh mesh = torusMeshNaive(p.shape, m_, p.pose());
      context.outputs->add(mesh_name_ + "_naive.off",
                           [&](const std::string& path) { writeMesh(mesh, path, true, false); });
      context.report << "naive torus mesh: " << mesh.n_vertices()
                     << " vertices (seams duplicated)\n";
    }
  }

 private:
  TorusSamplingParameters p_;
  TorusMeshParameters m_;
  Eigen::Vector3f center_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f axis_ = Eigen::Vector3f::UnitZ();
  int points_ = 20000;
  double alpha_min_ = 0.0, alpha_max_ = 360.0, beta_min_ = 0.0, beta_max_ = 360.0;
  double normal_noise_ = 0.0;
  double spin_ = 0.0;
  bool mesh_ = false;
  bool naive_ = false;
  bool print_sites_ = false;
  std::string mesh_name_ = "torus_mesh";
};

}  // namespace

StageInfo torusSamplingInfo() {
  return {"torus_sampling",
          "points with analytic normals on a posed torus (rational Bézier quarters), optional "
          "stitched OpenMesh mesh",
          [] { return std::unique_ptr<Stage>(new TorusSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
