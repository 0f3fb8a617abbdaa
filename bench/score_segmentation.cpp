// Scores a segmentation of a scene from the scene_sampling stage against its true labels:
// Hungarian-matched mean IoU, point accuracy, type accuracy, and the parameter errors of matched
// segments of the right type (read from the tool's primitives.yaml, matched by label).
//
//   score_segmentation TRUTH.ply RESULT_DIR [--per-truth]
//
// TRUTH.ply carries the field truth_label (and truth_type); RESULT_DIR holds segments.ply (fields
// label and primitive, and the truth's fields when the tool carried them through: then those are
// used, in the result's point order) and primitives.yaml — slipfit's segmentation stage and
// bench/cgal_ransac both write them. Prints one line of key=value pairs; --per-truth first prints
// one line per true primitive (its points and type, the matched segment, its type, the IoU).
#include "slipfit/core/angle_units.h"
#include "slipfit/sampling/scene_sampler.h"
#include "slipfit/segmentation/segmentation_metrics.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/ply_io.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
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

/// The truth is scene_sampling's fixed scene: one label per fixed primitive, of its type, and
/// the median distance of each label's points to it within 5 % of the smallest radius (0.35; the
/// scene's noise is at most 1 % of the object size).
bool isFixedScene(const std::string& file, const std::vector<std::int32_t>& truth,
                  const std::vector<int>& truth_types,
                  const std::vector<slipfit::ScenePrimitive>& fixed_scene) {
  if (truth_types.size() != fixed_scene.size())
    return false;
  for (std::size_t l = 0; l < fixed_scene.size(); ++l)
    if (truth_types[l] != static_cast<int>(slipfit::typeOf(fixed_scene[l].primitive)))
      return false;
  pcl::PointCloud<pcl::PointXYZ> xyz;
  if (pcl::io::loadPLYFile(file, xyz) < 0 || xyz.size() != truth.size())
    return false;
  std::vector<std::vector<double>> distances(fixed_scene.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (truth[i] >= 0)
      distances[static_cast<std::size_t>(truth[i])].push_back(
          slipfit::distance(xyz[i].getVector3fMap().cast<double>(),
                            fixed_scene[static_cast<std::size_t>(truth[i])].primitive));
  for (auto& d : distances) {
    if (d.empty())
      return false;
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    if (d[d.size() / 2] > 0.05 * 0.35)
      return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) try {
  const bool detail = argc == 4 && std::string(argv[3]) == "--per-truth";
  if (argc != 3 && !detail) {
    std::cerr << "usage: score_segmentation TRUTH.ply RESULT_DIR [--per-truth]\n";
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

  // The true type of each label: the field truth_type (both layouts write it), else the fixed
  // scene's. Parameter errors need the true parameters: the fixed scene's only, recognised by its
  // labels' types and by its points lying on its primitives.
  const auto& fixed_scene = slipfit::scenePrimitives();
  std::vector<int> truth_types;
  bool fixed = true;
  try {
    const std::vector<std::int32_t> ttype = intField(truth_file, "truth_type");
    for (std::size_t i = 0; i < truth.size(); ++i)
      if (truth[i] >= 0) {
        const auto l = static_cast<std::size_t>(truth[i]);
        if (truth_types.size() <= l)
          truth_types.resize(l + 1, -1);
        truth_types[l] = ttype[i];
      }
    fixed = isFixedScene(truth_file, truth, truth_types, fixed_scene);
  } catch (const std::runtime_error&) {
    for (const auto& p : fixed_scene)
      truth_types.push_back(static_cast<int>(slipfit::typeOf(p.primitive)));
  }
  const std::vector<slipfit::ScenePrimitive> no_parameters;
  const auto& scene = fixed ? fixed_scene : no_parameters;
  std::int32_t segments = 0;
  for (std::int32_t l : label)
    segments = std::max(segments, l + 1);
  std::vector<int> predicted_types(static_cast<std::size_t>(segments), -1);
  for (std::size_t i = 0; i < label.size(); ++i)
    if (label[i] >= 0)
      predicted_types[static_cast<std::size_t>(label[i])] = type[i];
  const slipfit::SegmentationScore score =
      slipfit::scoreSegmentation(truth, label, truth_types, predicted_types);
  if (detail) {
    // Per true primitive: its points, type, the matched segment, its type and the IoU.
    std::vector<std::size_t> points(score.iou.size(), 0);
    for (std::int32_t t : truth)
      if (t >= 0)
        ++points[static_cast<std::size_t>(t)];
    for (std::size_t t = 0; t < score.iou.size(); ++t) {
      if (points[t] == 0)
        continue;
      const int k = score.match[t];
      const int true_type = t < truth_types.size() ? truth_types[t] : -1;
      const int found_type = k >= 0 ? predicted_types[static_cast<std::size_t>(k)] : -1;
      std::cout << "truth " << t << " points=" << points[t] << " type=" << true_type
                << " segment=" << k << " segment_type=" << found_type << " iou=" << std::fixed
                << std::setprecision(3) << score.iou[t] << std::defaultfloat << "\n";
    }
  }

  // Parameters of the matched segments of the right type.
  std::map<int, YAML::Node> records;
  const YAML::Node report = YAML::LoadFile(dir + "/primitives.yaml")["primitives"];
  for (std::size_t j = 0; j < report.size(); ++j)
    records[report[j]["label"].as<int>()] = report[j];
  double angle_sum = 0, angle_max = 0, radius_sum = 0, radius_max = 0;
  int angles = 0, radii = 0, matched = 0, fitted = 0;
  for (std::size_t t = 0; t < score.truths && t < scene.size(); ++t) {
    const int k = score.match[t];
    if (k < 0 || predicted_types[static_cast<std::size_t>(k)] != truth_types[t] ||
        !records.count(k))
      continue;
    ++matched;
    const YAML::Node& r = records[k];
    if (r["status"] && r["status"].as<std::string>() != "ok")
      continue;  // a failed fit has no parameters to compare (it is counted in unfitted=)
    ++fitted;
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
            << " size_err_pct_max=" << 100 * radius_max << " unfitted=" << matched - fitted << "\n";
  return 0;
} catch (const std::exception& e) {
  std::cerr << "score_segmentation: " << e.what() << "\n";
  return 1;
}
