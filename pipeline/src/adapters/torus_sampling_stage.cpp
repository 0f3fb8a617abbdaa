#include "adapters.h"

#include "slipfit/core/angle_units.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/mesh_io.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/sampling/torus_sampler.h"

#include <iomanip>
#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class TorusSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(p_);
    o.add("mesh", mesh_, "Also write the stitched quad mesh as OFF (with normals, NOFF) and PLY.");
    o.add("mesh_name", mesh_name_, "Base name of the mesh files in the output dir.").fileName();
    o.bind(m_);
    o.add("mesh_naive", naive_,
          "Also write <mesh_name>_naive.off: four separate quarter meshes with duplicated seam "
          "vertices and face-averaged normals, to compare with the stitched mesh.");
    o.add("print_sites", print_sites_,
          "Print the 9 homogeneous Bézier sites [w; x, y, z] of each quarter patch.");
  }

  void prepare() override {
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
  TorusSamplingParameters p_ = [] {
    TorusSamplingParameters p;
    p.points = 20000;  // the stage's default (the library's is 10,000)
    return p;
  }();
  TorusMeshParameters m_;
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
