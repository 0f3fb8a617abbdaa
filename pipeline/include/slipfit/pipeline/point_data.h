#pragma once
/// \file What flows between pipeline stages: a PCL cloud plus the per-point fields and shared
/// structures that stages add.

#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/slippage/slippage.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace slipfit::pipeline {

/// One named per-point value written to the output PLY as a scalar property (a SlippageType as
/// its int code).
struct PointField {
  std::string name;
  std::variant<std::vector<std::int32_t>, std::vector<float>, std::vector<std::uint8_t>,
               std::vector<SlippageType>>
      values;
};

/// The field of slippage_classification's local mode that carries each point's slippage type
/// (kLocalSlippage): typed between stages, written as an int property.
inline constexpr const char* kSlippageTypeField = "slippage_type";

/// Data capabilities a stage may require or produce (bit flags).
enum DataBits : unsigned {
  kPoints = 1u << 0,
  kNormals = 1u << 1,
  kNeighborhoods = 1u << 2,
  /// The per-point local slippage fields (slippage_type, ...) of slippage_classification's local
  /// mode: the segmentation's seeds.
  kLocalSlippage = 1u << 3,
};

/// Where a range sensor stood: a PCD's VIEWPOINT (PCL's sensor_origin_ / sensor_orientation_),
/// and the rows and columns of an organized cloud (before its NaN points were dropped).
struct SensorPose {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  std::uint32_t width = 0, height = 0;  ///< organized: height > 1
};

/// The input's coordinate frame. Double-precision input far from the origin (georeferenced
/// LiDAR: x + 5e5, y + 5.4e6) is held at its coordinates minus `shift`, where float keeps its
/// detail, as CloudCompare's and PDAL's global shift; every output is written back in the input's
/// frame (coordinates + shift, as double when the input had double coordinates).
struct CoordinateFrame {
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();
  bool double_coordinates = false;  ///< the input stored x, y, z as double: the outputs do too
  /// A LAS input's coordinate grid (its integers × grid_scale + grid_offset) and point data record
  /// format: a LAS output keeps them. Zero scale: the input was not LAS.
  Eigen::Vector3d grid_scale = Eigen::Vector3d::Zero(), grid_offset = Eigen::Vector3d::Zero();
  int las_format = -1;
};

/// The pipeline's state. Every per-point array is aligned with `cloud`.
struct PointData {
  /// Coordinates, and normals + curvature when has_normals (else NaN).
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud{new pcl::PointCloud<pcl::PointNormal>};
  bool has_normals = false;
  /// Set when the input is a sensor's view (an organized cloud, or a PCD with a VIEWPOINT other
  /// than the identity at the origin): the picture is then taken from the sensor.
  std::optional<SensorPose> sensor;
  /// Each point's pixel in the sensor's width × height image (row × width + column) when the
  /// input is organized (an organized PCD, a simulated scan); empty otherwise, and after a
  /// subsample that dropped points (its points stand for voxels, not pixels).
  std::vector<std::int32_t> pixels;
  /// Where `cloud`'s coordinates are: the input's frame minus frame.shift.
  CoordinateFrame frame;
  /// curvature holds a meaningful value (set by normal estimation).
  bool has_curvature = false;
  /// The input's other fields (colour, intensity, ...), carried through unchanged.
  pcl::PCLPointCloud2 extra;
  /// Fields added by stages, written after the extra fields.
  std::vector<PointField> fields;
  /// Neighborhoods of every point, shared by later stages (kNeighborhoods).
  std::shared_ptr<const Neighborhoods> neighborhoods;

  /// Set by the subsample stage: the full-resolution data this (analysis) data stands for, and
  /// for each full point the index of its representative here.
  std::shared_ptr<PointData> full;
  std::vector<std::int32_t> representative;
  /// Set with `full` when each analysis point lies at the mean of the points it represents.
  bool averaged = false;

  std::size_t size() const { return cloud->size(); }
  unsigned available() const {
    return kPoints | (has_normals ? kNormals : 0u) | (neighborhoods ? kNeighborhoods : 0u);
  }
  /// Adds a field, replacing one of the same name.
  void setField(PointField field);
  const PointField* field(const std::string& name) const;
  /// The local slippage type of every point (kLocalSlippage); nullptr when no stage set it.
  const std::vector<SlippageType>* localSlippage() const;
  /// The values of a numeric per-point field, from the stage fields or the input's extra fields;
  /// empty when there is no such field (or it has count != 1).
  std::vector<double> numericField(const std::string& name) const;
  /// Keeps the points with keep[i] != 0, in order, in every per-point array; neighbor lists lose
  /// the removed points and are renumbered. `cloud` is replaced, never changed in place (another
  /// PointData may share it), and the memory of the removed points is released.
  void keepOnly(const std::vector<char>& keep);
  /// The same for the points \a kept (ascending, each once), as PCL's filters select them.
  void keepOnly(const pcl::Indices& kept);
  /// Replaces analysis data by its full-resolution data (no-op without `full`): coordinates and
  /// the input's fields from `full`, normals, curvature and stage fields copied from each point's
  /// representative. Neighborhoods are dropped (they belonged to the analysis points).
  /// With \a stage_fields false the analysis's stage fields are dropped instead of expanded.
  void expandToFull(bool stage_fields = true);
};

/// The data of a sampler: 3 × N points and, when \a with_normals, their 3 × N normals (else the
/// normals are NaN and has_normals false); curvature 0.
PointData sampledPointData(const Eigen::Matrix3Xd& points, const Eigen::Matrix3Xd& normals,
                           bool with_normals = true);

/// "points", "normals, neighborhoods" ...
std::string dataBitsText(unsigned bits);

}  // namespace slipfit::pipeline
