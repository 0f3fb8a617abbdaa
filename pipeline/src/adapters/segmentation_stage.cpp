#include "adapters.h"

#include "../las/las_writer.h"
#include "../png_file.h"
#include "slipfit/core/angle_units.h"
#include "slipfit/core/cloud_maps.h"
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/primitives_report.h"
#include "slipfit/pipeline/progress.h"
#include "slipfit/pipeline/tile_roles.h"
#include "slipfit/render/legend.h"
#include "slipfit/render/segment_palette.h"
#include "slipfit/render/splat_renderer.h"
#include "slipfit/segmentation/segment_axis.h"
#include "slipfit/segmentation/segmentation.h"
#include "slipfit/segmentation/segmentation_carry_back.h"
#include "slipfit/slippage/shape_classification.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <utility>

namespace slipfit::pipeline::adapters {

namespace {

Eigen::Vector3d pointAt(const pcl::PointCloud<pcl::PointNormal>& cloud, int i) {
  return cloud[static_cast<std::size_t>(i)].getVector3fMap().cast<double>();
}

class SegmentationStage : public Stage, public JoinedAcrossTiles {
 public:
  void declare(OptionSet& o) override {
    o.bind(parameters_);
    o.add("report", report_, "File name of the YAML report (one entry per segment).").fileName();
    o.add("segments", segments_,
          "File name of the PLY of every point with label, primitive and red/green/blue.")
        .fileName(".ply");
    o.add("pcd", pcd_,
          "File name of a PCD of the same points in PCL's conventions: label as uint32 "
          "(4294967295: no segment), the segment colour as packed rgb; organized like the input "
          "when that was a sensor's organized view (empty: none).")
        .allowEmpty()
        .fileName(".pcd");
    o.add("las", las_,
          "File name of a LAS 1.4 of the same points: the input's point records (its record "
          "format and coordinate grid when it was LAS) with label and primitive as extra bytes "
          "(empty: none).")
        .allowEmpty()
        .fileName(".las");
    o.add("local_copy", local_copy_,
          "File name of a float copy of the segments PLY in the local frame: coordinates less "
          "primitives.yaml's global_shift, for tools that read float only (empty: none; the "
          "same file as the segments PLY when the input has no shift).")
        .allowEmpty()
        .fileName(".ply");
    o.add("segment_files", segment_files_, "Also write each segment as segment_<label>.ply.");
    o.add("render", render_,
          "File name of a PNG picture of the segments, each kinematic segment with its axis "
          "(empty: none).")
        .allowEmpty()
        .fileName(".png");
    o.bind(render_parameters_);
  }

  void prepare() override {
    parameters_.validate();
    render_parameters_.validate();
  }

  DataFlow flow() const override {
    return {kPoints | kNormals | kNeighborhoods | kLocalSlippage, 0u};
  }

  std::vector<std::string> outputFiles() const override {
    std::vector<std::string> names = {report_, segments_};
    if (!pcd_.empty())
      names.push_back(pcd_);
    if (!las_.empty())
      names.push_back(las_);
    if (!local_copy_.empty())
      names.push_back(local_copy_);
    if (!render_.empty())
      names.push_back(render_);
    return names;
  }

  Files joinedFiles() const override { return {report_, segments_, las_}; }
  std::string unjoinedOutput() const override {
    return segment_files_         ? "segment_files"
           : !pcd_.empty()        ? "pcd"
           : !local_copy_.empty() ? "local_copy"
                                  : "";
  }
  std::string unjoinedSetting() const override {
    return parameters_.surfaces == SegmentSurfaces::kinematic ? "surfaces: kinematic" : "";
  }
  std::optional<RenderRequest> picture() const override {
    if (render_.empty())
      return std::nullopt;
    return RenderRequest{render_, render_parameters_};
  }
  void forTile(double share) override {
    render_.clear();
    las_.clear();
    parameters_.noise_sample_share = share;
  }

  void run(PointData& data, RunContext& context) override {
    const std::vector<SlippageType>* local = data.localSlippage();
    if (!local || local->size() != data.size())
      throw RunError(
          "segmentation needs the per-point field 'slippage_type': run slippage_classification "
          "with mode: local before it");
    if (!context.outputs)
      throw RunError("no output directory for the segmentation outputs");
    if (!coordinates(*data.cloud).allFinite())
      throw RunError("segmentation: some points are not finite");
    SegmentationParameters parameters = parameters_;
    parameters.threads = context.threads;
    parameters.sensor_view = data.sensor.has_value();  // organized, or a PCD's VIEWPOINT
    // The PCL front end, called as a PCL application calls it (the analysis copies in doubles
    // live only inside segment()).
    SlippageSegmentation<pcl::PointNormal> segmentation;
    segmentation.setInputCloud(data.cloud);
    segmentation.setNeighborhoods(data.neighborhoods);
    segmentation.setLocalTypes(std::shared_ptr<const std::vector<SlippageType>>(
        std::shared_ptr<void>(), local));  // a view: the field outlives the call
    segmentation.setParameters(parameters);
    segmentation.setPhaseListener(
        [&](std::string_view phase) { context.progress.note(std::string(phase)); });
    std::vector<pcl::PointIndices> clusters;
    segmentation.segment(clusters);
    SegmentationResult result = segmentation.releaseResult();
    if (data.full)
      carryToFull(data, result, context.threads, context.fields_used_later);

    std::vector<std::int32_t> primitive(data.size(), -1);
    std::vector<std::uint8_t> red(data.size()), green(data.size()), blue(data.size());
    for (std::size_t i = 0; i < data.size(); ++i) {
      const std::int32_t label = result.labels[i];
      const Rgb c = label < 0 ? kUnassignedColour : segmentColour(static_cast<std::size_t>(label));
      red[i] = c[0];
      green[i] = c[1];
      blue[i] = c[2];
      if (label >= 0)
        primitive[i] = segmentTypeCode(result.segments[static_cast<std::size_t>(label)]);
    }
    data.setField({"label", result.labels});
    data.setField({"primitive", std::move(primitive)});
    data.setField({"red", std::move(red)});
    data.setField({"green", std::move(green)});
    data.setField({"blue", std::move(blue)});

    writeReport(result, *data.cloud, data.frame.shift, context);
    writeClouds(data, result, context);
    if (!render_.empty())
      writeRender(data, result, context);

    std::size_t assigned = 0;
    for (const auto& s : result.segments)
      assigned += s.indices.size();
    if (result.segments.empty()) {
      context.report << "segmentation: no segment: no part of the cloud is a plane, sphere, "
                        "cylinder, cone or torus within distance "
                     << result.distance << " and at least " << result.min_points << " points ("
                     << result.regions_grown << " regions grown, " << result.volumes
                     << " of them random volumes, not surfaces); the report is empty\n";
      return;
    }
    context.report << "segmentation: " << result.segments.size() << " segments, " << assigned << "/"
                   << data.size() << " points assigned (distance " << result.distance << ", "
                   << result.merges << " merges, " << result.absorbed << " fragments absorbed, "
                   << result.fillets << " fillets, " << result.volumes
                   << " regions dropped as volumes or depth slices)\n";
    if (result.noise_range.second > result.noise_range.first)
      context.report << "  noise: σ " << result.noise_range.first << " to "
                     << result.noise_range.second
                     << " (5th to 95th percentile over the points; each point's tolerance is 3 "
                        "of its own σ)\n";
    context.report << "  phases:" << std::fixed << std::setprecision(2);
    for (const PhaseTiming& t : result.timings)
      context.report << " " << t.phase << " " << t.seconds << " s"
                     << (&t == &result.timings.back() ? "" : ",");
    context.report << std::defaultfloat << std::setprecision(6) << "\n";
    if (result.lattice.detected())
      context.report << "segmentation: " << result.lattice.name() << " is recorded on levels up to "
                     << result.lattice.maxStep()
                     << " apart: each point's tolerance adds its local step\n";
    constexpr std::size_t kListed = 20;
    for (std::size_t k = 0; k < result.segments.size() && k < kListed; ++k) {
      const Segment& s = result.segments[k];
      context.report << "  segment " << k << ": " << segmentTypeName(s) << ", " << s.indices.size()
                     << " points, rms " << s.rms_distance << "\n";
    }
    if (result.segments.size() > kListed)
      context.report << "  … and " << result.segments.size() - kListed
                     << " more segments (all in the outputs)\n";
  }

 private:
  /// The analysis ran on a subsample: every input point takes, among the segments of its
  /// representative and of the representative's neighbors, the one whose primitive is nearest,
  /// when within the distance tolerance (else −1); the segments' members and distances are then
  /// those of the full cloud (the fits stay the analysis fits).
  static void carryToFull(PointData& data, SegmentationResult& result, int threads,
                          bool stage_fields) {
    const std::vector<std::int32_t> representative = data.representative;
    const std::shared_ptr<const Neighborhoods> hoods = data.neighborhoods;
    const bool averaged = data.averaged;
    data.expandToFull(stage_fields);
    carrySegmentationBack(coordinates(*data.cloud), representative, *hoods, result, threads,
                          averaged);
  }

  void writeReport(const SegmentationResult& result, const pcl::PointCloud<pcl::PointNormal>& cloud,
                   const Eigen::Vector3d& shift, RunContext& context) const {
    std::vector<PrimitiveRecord> records;
    for (std::size_t k = 0; k < result.segments.size(); ++k) {
      const Segment& s = result.segments[k];
      PrimitiveRecord r;
      r.id = static_cast<int>(k);
      r.label = static_cast<int>(k);
      r.fit = s.fit;
      r.fit.rms_distance = s.rms_distance;
      r.fit.max_distance = s.max_distance;
      r.fit.used_points = s.fit.used_points;  // the points the fit saw (the analysis points)
      r.slippage = s.slippage;
      if (s.kinematic) {
        // A kinematic segment: its class and fitted surface, as a whole-cloud kinematic verdict.
        r.fitted = false;
        r.kinematic = s.kinematic;
        SlippageResult kinematic;
        kinematic.type = slippageTypeOf(s.kinematic->surface.type);
        kinematic.motions = 1;
        kinematic.axis = s.kinematic->surface.axis;
        r.slippage = kinematic;
      }
      r.inlier_distance = result.distance;
      for (int i : s.indices)
        r.inliers += result.explains(s, pointAt(cloud, i)) ? 1 : 0;
      r.extra["points"] = std::to_string(s.indices.size());
      r.extra["seed_slippage_type"] = std::string(slippageTypeName(s.seed_type));
      records.push_back(std::move(r));
    }
    context.outputs->addText(report_, primitivesYaml(records, "slipfit segmentation", shift));
  }

  void writeClouds(const PointData& data, const SegmentationResult& result,
                   RunContext& context) const {
    PointData view;
    view.cloud = data.cloud;
    view.frame = data.frame;
    view.sensor = data.sensor;  // the PCD's VIEWPOINT
    view.pixels = data.pixels;  // an organized input gives an organized PCD (a label image)
    view.has_normals = true;
    view.extra = data.extra;  // the input's own fields (colour, intensity, labels) come along
    for (const char* name : {"label", "primitive", "red", "green", "blue"})
      view.setField(*data.field(name));
    context.outputs->add(segments_,
                         [&](const std::string& path) { writeCloudPly(view, path, true); });
    if (!pcd_.empty())
      context.outputs->add(pcd_, [&](const std::string& path) { writeCloudPcd(view, path); });
    if (!las_.empty())
      context.outputs->add(las_, [&](const std::string& path) {
        las::writeLas(view, path, {"label", "primitive"});
      });
    if (!local_copy_.empty()) {
      PointData local = view;
      local.frame = CoordinateFrame{};  // the cloud's own float coordinates: input − shift
      context.outputs->add(local_copy_,
                           [&](const std::string& path) { writeCloudPly(local, path, true); });
    }
    if (!segment_files_)
      return;
    for (std::size_t k = 0; k < result.segments.size(); ++k) {
      PointData part;
      part.has_normals = true;
      part.frame = data.frame;
      for (int i : result.segments[k].indices)
        part.cloud->push_back((*data.cloud)[static_cast<std::size_t>(i)]);
      context.outputs->add("segment_" + std::to_string(k) + ".ply",
                           [&](const std::string& path) { writeCloudPly(part, path, true); });
    }
  }

  void writeRender(const PointData& data, const SegmentationResult& result,
                   RunContext& context) const {
    const auto n = static_cast<Eigen::Index>(data.size());
    // Views of the cloud's coordinates and normals (a PointNormal is 12 floats): no copies.
    using Strided = Eigen::Map<const Eigen::Matrix3Xf, 0, Eigen::OuterStride<>>;
    const Eigen::OuterStride<> stride(sizeof(pcl::PointNormal) / sizeof(float));
    const Strided x(&(*data.cloud)[0].x, 3, n, stride);
    const Strided nn(&(*data.cloud)[0].normal_x, 3, n, stride);
    Eigen::Matrix<std::uint8_t, 3, Eigen::Dynamic> rgb(3, n);
    const auto& red = std::get<std::vector<std::uint8_t>>(data.field("red")->values);
    const auto& green = std::get<std::vector<std::uint8_t>>(data.field("green")->values);
    const auto& blue = std::get<std::vector<std::uint8_t>>(data.field("blue")->values);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      rgb.col(i) << red[u], green[u], blue[u];
    }
    // A sensor's view is rendered from the sensor unless the config places the camera.
    RenderParameters camera = render_parameters_;
    if (camera.eye)
      *camera.eye -= data.frame.shift;  // the config's eye is in the input's frame
    if (!render_parameters_.eye && data.sensor)
      useSensorCamera(camera, data.sensor->origin, data.sensor->orientation, x, -data.frame.shift);
    // Each kinematic segment's axis, over the stretch its points cover and a sixth more.
    std::vector<RenderLine> axes;
    for (std::size_t k = 0; k < result.segments.size(); ++k)
      if (const auto ends = axisStretch(result.segments[k], x, 1.0 / 6.0)) {
        RenderLine line;
        line.from = (*ends)[0];
        line.to = (*ends)[1];
        const Rgb c = segmentColour(k);
        std::copy(c.begin(), c.end(), line.colour);
        axes.push_back(line);
      }
    std::vector<std::uint8_t> image = renderSplats(x, rgb, nn, camera, axes);
    if (camera.legend) {
      std::vector<std::string> types;
      std::vector<std::size_t> points;
      std::size_t assigned = 0;
      for (const Segment& s : result.segments) {
        types.emplace_back(segmentTypeName(s));
        points.push_back(s.indices.size());
        assigned += s.indices.size();
      }
      drawLegend(image, camera.width, camera.height,
                 segmentLegend(types, points, data.size() - assigned), legendScale(camera.height),
                 kLegendRows);
    }
    context.outputs->add(render_, [&](const std::string& path) {
      detail::writeRgbPng(path, image, camera.width, camera.height);
    });
  }

  SegmentationParameters parameters_;
  RenderParameters render_parameters_;
  std::string report_ = "primitives.yaml", segments_ = "segments.ply", render_ = "segments.png",
              pcd_, las_, local_copy_;
  bool segment_files_ = false;
};

}  // namespace

StageInfo segmentationInfo() {
  return {
      "segmentation",
      "segments the cloud into planes, spheres, cylinders, cones and tori by region growing from "
      "the local slippage; writes primitives.yaml, segments.ply and a PNG picture",
      [] { return std::unique_ptr<Stage>(new SegmentationStage); }};
}

}  // namespace slipfit::pipeline::adapters
