// CGAL's Efficient RANSAC (Schnabel, Wahl & Klein 2007) on a slipfit cloud with normals, for the
// side-by-side comparison of bench/run_segmentation.sh. Writes the same outputs as slipfit's
// segmentation stage: a PLY with per-point `label` and `primitive` (−1 unassigned; 0 plane,
// 1 sphere, 2 cylinder, 3 cone, 4 torus) and a primitives.yaml with the same parameter names.
//
//   cgal_ransac IN.ply OUT_DIR [default|tuned] [seed] [given|pca]
//
// given: use the normals in IN.ply; pca: estimate them first with CGAL::pca_estimate_normals
// (k = 18, parallel with TBB when available) — the whole pipeline a CGAL user would run.
//
// default: CGAL's documented defaults scaled to the cloud (epsilon and cluster_epsilon 1 % of the
// bounding-box diagonal, normal_threshold 0.9, min_points 1 % of N, probability 0.05);
// tuned: the best setting found for these scenes (see bench/README.md).
#include "slipfit/pipeline/cloud_io.h"

#include <pcl/io/ply_io.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Shape_detection/Efficient_RANSAC.h>
#include <CGAL/pca_estimate_normals.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <tuple>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// CGAL reorders its input during detection: each point carries its index in the cloud.
using PointWithNormal = std::tuple<Kernel::Point_3, Kernel::Vector_3, std::size_t>;
using PointVector = std::vector<PointWithNormal>;
using PointMap = CGAL::Nth_of_tuple_property_map<0, PointWithNormal>;
using NormalMap = CGAL::Nth_of_tuple_property_map<1, PointWithNormal>;
using Traits =
    CGAL::Shape_detection::Efficient_RANSAC_traits<Kernel, PointVector, PointMap, NormalMap>;
using EfficientRansac = CGAL::Shape_detection::Efficient_RANSAC<Traits>;

namespace sd = CGAL::Shape_detection;

namespace {

std::string vec(const Kernel::Vector_3& v) {
  std::ostringstream s;
  s << std::setprecision(17) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}
std::string pt(const Kernel::Point_3& p) {
  return vec(p - CGAL::ORIGIN);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: cgal_ransac IN.ply OUT_DIR [default|tuned] [seed] [given|pca] "
                 "[epsilon cluster_epsilon min_points]\n";
    return 2;
  }
  const std::string setting = argc > 3 ? argv[3] : "default";
  const unsigned seed = argc > 4 ? static_cast<unsigned>(std::stoul(argv[4])) : 1u;
  const std::string normals = argc > 5 ? argv[5] : "given";
  // PCL's reader: slipfit's outputs mark points that were not analysed with NaN normals, which
  // slipfit's own reader rejects; such points are left out of CGAL's input (label −1).
  slipfit::pipeline::PointData data;
  if (pcl::io::loadPLYFile(argv[1], *data.cloud) < 0) {
    std::cerr << "cgal_ransac: cannot read " << argv[1] << "\n";
    return 1;
  }
  data.has_normals = true;
  PointVector points;
  points.reserve(data.size());
  Eigen::AlignedBox3f box;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const auto& p = (*data.cloud)[i];
    if (!p.getVector3fMap().allFinite() ||
        (normals == "given" && !p.getNormalVector3fMap().allFinite()))
      continue;
    points.emplace_back(Kernel::Point_3(p.x, p.y, p.z),
                        Kernel::Vector_3(p.normal_x, p.normal_y, p.normal_z), i);
    box.extend(p.getVector3fMap());
  }
  if (points.empty()) {
    std::cerr << "cgal_ransac: " << argv[1] << " has no points with normals\n";
    return 1;
  }
  const double diagonal = box.diagonal().norm();
  const auto n = points.size();
  const std::size_t total = data.size();

  CGAL::get_default_random() = CGAL::Random(seed);
  const auto start = std::chrono::steady_clock::now();
  if (normals == "pca")
    CGAL::pca_estimate_normals<CGAL::Parallel_if_available_tag>(
        points, 18, CGAL::parameters::point_map(PointMap()).normal_map(NormalMap()));
  else if (normals != "given") {
    std::cerr << "cgal_ransac: normals must be given or pca\n";
    return 2;
  }
  if (normals == "pca")
    for (const auto& [p, nrm, index] : points)
      (*data.cloud)[index].getNormalVector3fMap() = Eigen::Vector3f(
          static_cast<float>(nrm.x()), static_cast<float>(nrm.y()), static_cast<float>(nrm.z()));
  const double normal_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EfficientRansac ransac;
  ransac.set_input(points);
  ransac.add_shape_factory<sd::Plane<Traits>>();
  ransac.add_shape_factory<sd::Sphere<Traits>>();
  ransac.add_shape_factory<sd::Cylinder<Traits>>();
  ransac.add_shape_factory<sd::Cone<Traits>>();
  ransac.add_shape_factory<sd::Torus<Traits>>();
  EfficientRansac::Parameters parameters;
  parameters.probability = 0.05;
  parameters.min_points = n / 100;
  parameters.epsilon = 0.01 * diagonal;
  parameters.cluster_epsilon = 0.01 * diagonal;
  parameters.normal_threshold = 0.9;
  if (setting == "tuned") {
    // Tighter distance (the scenes' noise is far below 1 % of the diagonal), smaller shapes
    // allowed, more endurance.
    parameters.probability = 0.01;
    parameters.min_points = std::max<std::size_t>(30, n / 500);
    parameters.epsilon = 0.004 * diagonal;
    parameters.cluster_epsilon = 0.01 * diagonal;
    parameters.normal_threshold = 0.85;
  } else if (setting != "default") {
    std::cerr << "cgal_ransac: setting must be default or tuned\n";
    return 2;
  }
  if (argc > 8) {
    // Explicit values for scenes whose noise and smallest shape are known (random scenes).
    parameters.epsilon = std::stod(argv[6]);
    parameters.cluster_epsilon = std::stod(argv[7]);
    parameters.min_points = std::stoul(argv[8]);
  }
  ransac.detect(parameters);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<std::int32_t> label(total, -1), primitive(total, -1);
  std::ostringstream yaml;
  yaml << "source: CGAL Efficient_RANSAC (" << setting << ")\nprimitives:\n";
  int id = 0;
  for (const auto& shape : ransac.shapes()) {
    int type = -1;
    yaml << "  - id: " << id << "\n    label: " << id << "\n";
    if (auto* plane = dynamic_cast<sd::Plane<Traits>*>(shape.get())) {
      type = 0;
      const Kernel::Plane_3 p = *plane;
      const Kernel::Vector_3 nrm =
          p.orthogonal_vector() / std::sqrt(p.orthogonal_vector().squared_length());
      yaml << "    type: plane\n    normal: " << vec(nrm) << "\n    d: " << std::setprecision(17)
           << -p.d() / std::sqrt(p.orthogonal_vector().squared_length()) << "\n";
    } else if (auto* sphere = dynamic_cast<sd::Sphere<Traits>*>(shape.get())) {
      type = 1;
      yaml << "    type: sphere\n    center: " << pt(sphere->center())
           << "\n    radius: " << std::setprecision(17) << sphere->radius() << "\n";
    } else if (auto* cylinder = dynamic_cast<sd::Cylinder<Traits>*>(shape.get())) {
      type = 2;
      const Kernel::Line_3 axis = cylinder->axis();
      const Kernel::Vector_3 d = axis.to_vector() / std::sqrt(axis.to_vector().squared_length());
      yaml << "    type: cylinder\n    axis: " << vec(d) << "\n    point: " << pt(axis.point())
           << "\n    radius: " << std::setprecision(17) << cylinder->radius() << "\n";
    } else if (auto* cone = dynamic_cast<sd::Cone<Traits>*>(shape.get())) {
      type = 3;
      yaml << "    type: cone\n    axis: " << vec(cone->axis())
           << "\n    apex: " << pt(cone->apex()) << "\n    half_angle: " << std::setprecision(17)
           << cone->angle() << "\n";
    } else {
      type = 4;
      yaml << "    type: torus\n";
    }
    yaml << "    points: " << shape->indices_of_assigned_points().size() << "\n";
    for (std::size_t i : shape->indices_of_assigned_points()) {
      const std::size_t original = std::get<2>(points[i]);
      label[original] = id;
      primitive[original] = type;
    }
    ++id;
  }

  slipfit::pipeline::PointData out;
  out.cloud = data.cloud;
  out.has_normals = true;
  out.setField({"label", label});
  out.setField({"primitive", primitive});
  const std::string dir = argv[2];
  slipfit::pipeline::writeCloudPly(out, dir + "/segments.ply", true);
  std::ofstream(dir + "/primitives.yaml") << yaml.str();
  std::cout << "cgal " << setting << ": " << id << " shapes, " << std::fixed << std::setprecision(3)
            << seconds - normal_seconds << " s detection, " << normal_seconds << " s normals\n";
  return 0;
}
