// Scores a segmentation of a scene from the scene_sampling stage against its true labels:
// Hungarian-matched mean IoU, point accuracy, type accuracy, and the parameter errors of matched
// segments of the right type (read from the tool's primitives.yaml, matched by label).
//
//   score_segmentation TRUTH.ply RESULT_DIR
//
// TRUTH.ply carries the field truth_label (and truth_type); RESULT_DIR holds segments.ply (fields
// label and primitive, and the truth's fields when the tool carried them through: then those are
// used, in the result's point order) and primitives.yaml — slipfit's segmentation stage and
// bench/cgal_ransac both write them. Prints one line of key=value pairs.
#include "slipfit/core/angle_units.h"
#include "slipfit/sampling/scene_sampler.h"
#include "slipfit/segmentation/segmentation_metrics.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/ply_io.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <iomanip>
#include <iostream>
#include <map>

namespace {

using slipfit::kDegree;

/// An integer per-point field of a PLY, read through PCL directly: outputs may carry NaN normals
/// for points that were not analysed, which slipfit's own reader rejects.
std::vector<std::int32_t> intField(const std::string& file, const std::string& name) {
  pcl::PCLPointCloud2 blob;
  if (pcl::io::loadPLYFile(file, blob) < 0)
    throw std::runtime_error(file + ": cannot be read");
  for (const auto& f : blob.fields) {
    if (f.name != name || f.datatype != pcl::PCLPointField::INT32)
      continue;
    std::vector<std::int32_t> out(blob.width * blob.height);
    for (std::size_t i = 0; i < out.size(); ++i)
      std::memcpy(&out[i], blob.data.data() + i * blob.point_step + f.offset, 4);
    return out;
  }
  throw std::runtime_error(file + ": no int field '" + name + "'");
}

Eigen::Vector3d vec(const YAML::Node& node) {
  return {node[0].as<double>(), node[1].as<double>(), node[2].as<double>()};
}

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) / kDegree;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc != 3) {
    std::cerr << "usage: score_segmentation TRUTH.ply RESULT_DIR\n";
    return 2;
  }
  const std::string dir = argv[2];
  const std::vector<std::int32_t> label = intField(dir + "/segments.ply", "label");
  const std::vector<std::int32_t> type = intField(dir + "/segments.ply", "primitive");
  // The result's own copy of the truth when it carries one (slipfit's outputs carry the input's
  // fields; a tiled run writes the points tile after tile, not in the input's order).
  std::vector<std::int32_t> truth;
  std::string truth_file = argv[1];
  try {
    truth = intField(dir + "/segments.ply", "truth_label");
    truth_file = dir + "/segments.ply";
  } catch (const std::runtime_error&) {
    truth = intField(argv[1], "truth_label");
  }
  if (truth.size() != label.size())
    throw std::runtime_error("the truth and the result differ in point count");

  // The true type of each label: the field truth_type (random scenes), else the fixed scene's.
  const auto& fixed_scene = slipfit::scenePrimitives();
  std::vector<slipfit::ScenePrimitive> no_parameters;
  std::vector<int> truth_types;
  bool random_scene = false;
  try {
    const std::vector<std::int32_t> ttype = intField(truth_file, "truth_type");
    random_scene = true;
    for (std::size_t i = 0; i < truth.size(); ++i)
      if (truth[i] >= 0) {
        const auto l = static_cast<std::size_t>(truth[i]);
        if (truth_types.size() <= l)
          truth_types.resize(l + 1, -1);
        truth_types[l] = ttype[i];
      }
  } catch (const std::runtime_error&) {
    for (const auto& p : fixed_scene)
      truth_types.push_back(static_cast<int>(slipfit::typeOf(p.primitive)));
  }
  // Parameter errors need the true parameters: the fixed scene's only.
  const auto& scene = random_scene ? no_parameters : fixed_scene;
  std::int32_t segments = 0;
  for (std::int32_t l : label)
    segments = std::max(segments, l + 1);
  std::vector<int> predicted_types(static_cast<std::size_t>(segments), -1);
  for (std::size_t i = 0; i < label.size(); ++i)
    if (label[i] >= 0)
      predicted_types[static_cast<std::size_t>(label[i])] = type[i];
  const slipfit::SegmentationScore score =
      slipfit::scoreSegmentation(truth, label, truth_types, predicted_types);

  // Parameters of the matched segments of the right type.
  std::map<int, YAML::Node> records;
  const YAML::Node report = YAML::LoadFile(dir + "/primitives.yaml")["primitives"];
  for (std::size_t j = 0; j < report.size(); ++j)
    records[report[j]["label"].as<int>()] = report[j];
  double angle_sum = 0, angle_max = 0, radius_sum = 0, radius_max = 0;
  int angles = 0, radii = 0;
  for (std::size_t t = 0; t < score.truths && t < scene.size(); ++t) {
    const int k = score.match[t];
    if (k < 0 || predicted_types[static_cast<std::size_t>(k)] != truth_types[t] ||
        !records.count(k))
      continue;
    const YAML::Node& r = records[k];
    double angle = -1, radius = -1;
    if (const auto* pl = std::get_if<slipfit::Plane>(&scene[t].primitive)) {
      angle = angleDeg(vec(r["normal"]), pl->normal);
    } else if (const auto* sp = std::get_if<slipfit::Sphere>(&scene[t].primitive)) {
      radius = std::abs(r["radius"].as<double>() - sp->radius) / sp->radius;
    } else if (const auto* cy = std::get_if<slipfit::Cylinder>(&scene[t].primitive)) {
      angle = angleDeg(vec(r["axis"]), cy->axis);
      radius = std::abs(r["radius"].as<double>() - cy->radius) / cy->radius;
    } else if (const auto* co = std::get_if<slipfit::Cone>(&scene[t].primitive)) {
      angle = angleDeg(vec(r["axis"]), co->axis);
      radius = std::abs(r["half_angle"].as<double>() - co->half_angle) / co->half_angle;
    }
    if (angle >= 0) {
      angle_sum += angle;
      angle_max = std::max(angle_max, angle);
      ++angles;
    }
    if (radius >= 0) {
      radius_sum += radius;
      radius_max = std::max(radius_max, radius);
      ++radii;
    }
  }
  std::size_t found = 0;
  for (int m : score.match)
    found += m >= 0 ? 1 : 0;
  std::cout << std::fixed << std::setprecision(4) << "mean_iou=" << score.mean_iou
            << " point_accuracy=" << score.point_accuracy
            << " type_accuracy=" << score.type_accuracy << " segments=" << score.segments
            << " truths=" << score.truths << " found=" << found
            << " axis_err_deg_mean=" << (angles ? angle_sum / angles : 0.0)
            << " axis_err_deg_max=" << angle_max
            << " size_err_pct_mean=" << (radii ? 100 * radius_sum / radii : 0.0)
            << " size_err_pct_max=" << 100 * radius_max << "\n";
  return 0;
} catch (const std::exception& e) {
  std::cerr << "score_segmentation: " << e.what() << "\n";
  return 1;
}
