#include "adapters.h"

#include "slipfit/core/cloud_maps.h"
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/mesh_io.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/primitives_report.h"
#include "slipfit/slippage/local_slippage.h"
#include "slipfit/slippage/shape_classification.h"
#include "slipfit/slippage/slippage.h"
#include "slipfit/surfaces/kinematic_mesh.h"

#include <fstream>
#include <memory>
#include <ostream>
#include <utility>

namespace slipfit::pipeline::adapters {

namespace {

enum class SlippageMode { whole, local };
constexpr std::array<std::pair<SlippageMode, std::string_view>, 2> kSlippageModeNames{{
    {SlippageMode::whole, "whole"},
    {SlippageMode::local, "local"},
}};

class SlippageStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("mode", mode_, kSlippageModeNames,
          "whole: one verdict for the whole cloud, written to the report (then fitted); local: "
          "per-point fields over the shared neighborhoods.");
    o.bind(options_);
    o.add("fit", fit_,
          "Whole mode: report the refined fit of a primitive verdict (every type is fitted to "
          "decide the verdict; see docs/THEORY.md §5.4).");
    o.add("report", report_, "Whole mode: file name of the YAML report in the output dir.")
        .fileName();
    o.add("mesh", mesh_,
          "Whole mode: when the verdict is a fitted kinematic surface, also write it as a quad "
          "mesh, its profile swept over the stretch of the motion the points cover.");
    o.add("mesh_name", mesh_name_, "File name of that mesh in the output dir.").fileName(".ply");
    o.add("mesh_steps", mesh_steps_, "Steps of the motion in that mesh.")
        .unit("steps")
        .range(1, 100000);
  }

  void prepare() override { options_.validate(); }

  DataFlow flow() const override {
    if (mode_ == SlippageMode::local)
      return {kPoints | kNormals | kNeighborhoods, kLocalSlippage};
    return {kPoints | kNormals, 0u};
  }

  std::vector<std::string> outputFiles() const override {
    if (mode_ != SlippageMode::whole)
      return {};
    if (mesh_)
      return {report_, mesh_name_};
    return {report_};
  }

  void run(PointData& data, RunContext& context) override {
    if (mode_ == SlippageMode::local)
      return runLocal(data, context);
    const Eigen::Matrix3Xd x = coordinates(*data.cloud).cast<double>();
    const Eigen::Matrix3Xd nn = normals(std::as_const(*data.cloud)).cast<double>();
    const Eigen::VectorXd w = Eigen::VectorXd::Ones(x.cols());
    PrimitiveRecord record;
    ShapeClassification c = classifyShape(x, nn, w, options_);
    record.slippage = c.verdict;
    const SlippageResult& s = c.verdict;
    context.report << "slippage: " << slippageTypeName(s.type) << ", " << s.motions
                   << " motions, spectrum " << s.spectrum.transpose() << ", gap " << s.gap
                   << ", threshold " << c.spectral.threshold << " (noise energy " << c.noise_energy
                   << "), surface noise " << c.noise
                   << (s.reason.empty() ? "" : " (" + s.reason + ")") << "\n";
    if (c.spectral.type != s.type)
      context.report << "  the spectrum alone reads " << slippageTypeName(c.spectral.type)
                     << "; the fits decide\n";
    for (const ShapeCandidate& k : c.candidates)
      if (k.fitted)
        context.report << "  " << primitiveTypeName(k.type) << ": rms " << k.rms
                       << (k.explains ? " (explains the points)" : "") << ", motion energy "
                       << k.energy << " (bound " << k.energy_bound << ")\n";
    if (c.kinematic)
      context.report << "  " << kinematicTypeName(c.kinematic->surface.type) << ": rms "
                     << c.kinematic->rms_distance
                     << (c.kinematic_explains ? " (explains the points)" : "") << ", profile of "
                     << c.kinematic->surface.profile.vertices.size() << " vertices ("
                     << parameterCount(c.kinematic->surface) << " parameters)"
                     << (c.kinematic_verdict ? ": the verdict" : "") << "\n";
    if (c.kinematic_verdict)
      record.kinematic = c.kinematic;
    if (mesh_ && c.kinematic_verdict)
      addMesh(c.kinematic->surface, x, data.frame.shift, context);
    else if (mesh_)
      context.report << "mesh: none (the verdict is not a fitted kinematic surface)\n";
    record.extra["surface_noise"] = std::to_string(c.noise);
    record.fitted = fit_ && c.fit.has_value();
    if (record.fitted) {
      record.fit = std::move(*c.fit);
      record.inlier_distance = c.inlier_distance;
      record.inliers = c.inliers;
      context.report << "fit: " << primitiveTypeName(record.fit.type) << ", rms "
                     << record.fit.rms_distance << "\n";
    }
    if (!context.outputs)
      throw RunError("no output directory for the report");
    context.outputs->addText(
        report_, primitivesYaml({record}, "slipfit slippage_classification", data.frame.shift));
  }

 private:
  void addMesh(KinematicSurface surface, const Eigen::Matrix3Xd& x, const Eigen::Vector3d& shift,
               RunContext& context) const {
    if (!context.outputs)
      throw RunError("no output directory for the mesh");
    auto mesh = std::make_shared<SurfaceMesh>(kinematicMesh(surface, x, mesh_steps_));
    // In the input's coordinates, as primitives.yaml's.
    for (const SurfaceMesh::VertexHandle v : mesh->vertices())
      mesh->point(v) += OpenMesh::Vec3d(shift.x(), shift.y(), shift.z());
    context.outputs->add(mesh_name_,
                         [mesh](const std::string& path) { writeMesh(*mesh, path, true, false); });
    context.report << "mesh: " << mesh_name_ << ", " << mesh->n_vertices() << " vertices, "
                   << mesh->n_faces() << " faces\n";
  }

  void runLocal(PointData& data, RunContext& context) {
    LocalSlippage<pcl::PointNormal> local;
    local.setInputCloud(data.cloud);
    local.setNeighborhoods(data.neighborhoods);
    local.setOptions(options_);
    local.setNumberOfThreads(context.threads);
    pcl::PointCloud<PointSlippage> out;
    local.compute(out);
    const std::size_t n = out.size();
    std::vector<std::int32_t> motions(n);
    std::vector<SlippageType> type(n);
    std::vector<float> ax(n), ay(n), az(n), gap(n);
    std::array<std::size_t, kSlippageTypeNames.size()> counts{};
    for (std::size_t i = 0; i < n; ++i) {
      motions[i] = out[i].motions;
      type[i] = static_cast<SlippageType>(out[i].slippage_type);
      ax[i] = out[i].axis_x;
      ay[i] = out[i].axis_y;
      az[i] = out[i].axis_z;
      gap[i] = out[i].gap;
      ++counts[static_cast<std::size_t>(out[i].slippage_type)];
    }
    data.setField({"slippable_motions", std::move(motions)});
    data.setField({kSlippageTypeField, std::move(type)});
    data.setField({"slip_axis_x", std::move(ax)});
    data.setField({"slip_axis_y", std::move(ay)});
    data.setField({"slip_axis_z", std::move(az)});
    data.setField({"slip_gap", std::move(gap)});
    context.report << "local slippage:";
    for (std::size_t t = 0; t < counts.size(); ++t)
      if (counts[t])
        context.report << " " << kSlippageTypeNames[t].second << " " << counts[t];
    context.report << "\n";
  }

  SlippageMode mode_ = SlippageMode::whole;
  SlippageOptions options_;
  bool fit_ = true;
  std::string report_ = "primitives.yaml";
  bool mesh_ = false;
  std::string mesh_name_ = "kinematic.ply";
  int mesh_steps_ = 96;
};

}  // namespace

StageInfo slippageClassificationInfo() {
  return {"slippage_classification",
          "slippable motions (Gelfand & Guibas 2004) of the whole cloud or of every neighborhood: "
          "type, axis/centre/apex/pitch, then the weighted fit",
          [] { return std::unique_ptr<Stage>(new SlippageStage); }};
}

}  // namespace slipfit::pipeline::adapters
