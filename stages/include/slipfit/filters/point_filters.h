#pragma once
/// \file The point filters of the pipeline's crop, voxel_grid and outlier_removal stages: PCL's
/// PassThrough and CropBox, UniformSampling and VoxelGrid, StatisticalOutlierRemoval and
/// RadiusOutlierRemoval, each behind a parameters type that declares its options once. Each
/// filter selects input points: it returns the indices it keeps (ascending) and a description of
/// why, for the report.

#include "slipfit/core/parameter_declaration.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/types.h>

#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slipfit {

/// The points a filter keeps, ascending, and the reason in words ("z in [0, 1.5]").
struct FilterSelection {
  pcl::Indices kept;
  std::string why;
};

enum class CropField { none, x, y, z };
constexpr std::array<std::pair<CropField, std::string_view>, 4> kCropFieldNames{{
    {CropField::none, "none"},
    {CropField::x, "x"},
    {CropField::y, "y"},
    {CropField::z, "z"},
}};

/// PassThrough on one coordinate and/or CropBox on an axis-aligned box; limits in the frame of
/// the input (the cloud's coordinates + shift, see crop()).
struct CropParameters {
  CropField field = CropField::none;
  std::optional<double> min, max;
  std::optional<Eigen::Vector3d> box_min, box_max;
  bool negative = false;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.field,
          parameter("field",
                    "PassThrough: the coordinate limited to [min, max] (PCL's cylinder tutorial "
                    "keeps z in [0, 1.5] of a Kinect scan)."),
          kCropFieldNames);
    visit(self.min,
          parameter("min", "PassThrough: the smallest value kept (inclusive).").in("cloud units"));
    visit(self.max,
          parameter("max", "PassThrough: the largest value kept (inclusive).").in("cloud units"));
    visit(self.box_min,
          parameter("box_min", "CropBox: the box's lowest corner [x, y, z].").in("cloud units"));
    visit(self.box_max,
          parameter("box_max", "CropBox: the box's highest corner [x, y, z].").in("cloud units"));
    visit(self.negative,
          parameter("negative",
                    "Keep the points outside the limits instead (every limit given is applied)."));
  }

  /// Throws InvalidParameterError when the limits are missing or contradict each other.
  void validate() const;
};

/// The points of \a cloud within (or, negative, outside) the limits. The cloud holds the input's
/// coordinates minus \a shift (pipeline/point_data.h's CoordinateFrame).
FilterSelection crop(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                     const CropParameters& parameters,
                     const Eigen::Vector3d& shift = Eigen::Vector3d::Zero());

enum class VoxelMethod { uniform, centroid };
constexpr std::array<std::pair<VoxelMethod, std::string_view>, 2> kVoxelMethodNames{{
    {VoxelMethod::uniform, "uniform"},
    {VoxelMethod::centroid, "centroid"},
}};

struct VoxelGridParameters {
  double leaf = 0.0;  ///< voxel edge, > 0 (no default: the stage requires it)
  VoxelMethod method = VoxelMethod::uniform;

  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.leaf, parameter("leaf", "Voxel edge.").in("cloud units").above(0).mustBeGiven());
    visit(self.method,
          parameter("method",
                    "uniform: each voxel keeps its input point nearest the voxel's centre, with "
                    "all its fields (PCL's UniformSampling); centroid: the point moves to the "
                    "centroid of its voxel's points (PCL's VoxelGrid), the other fields those of "
                    "the voxel's point nearest the centroid."),
          kVoxelMethodNames);
  }

  void validate() const;
};

/// One point per voxel of edge `leaf`; with method centroid, \a centroids receives the position
/// each kept point moves to (aligned with `kept`), else it is cleared. Throws
/// DegenerateInputError when the grid over the cloud's extent has more voxels than PCL's grids
/// can index (2^31: PCL would warn and return the cloud unchanged).
FilterSelection voxelGrid(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                          const VoxelGridParameters& parameters,
                          std::vector<Eigen::Vector3f>& centroids);

enum class OutlierMethod { statistical, radius };
constexpr std::array<std::pair<OutlierMethod, std::string_view>, 2> kOutlierMethodNames{{
    {OutlierMethod::statistical, "statistical"},
    {OutlierMethod::radius, "radius"},
}};

struct OutlierRemovalParameters {
  OutlierMethod method = OutlierMethod::statistical;
  int k = 50;
  double stddev = 1.0;
  std::optional<double> radius;
  int min_neighbors = 2;

  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.method,
          parameter("method",
                    "statistical: drop points whose mean distance to their k nearest neighbors "
                    "exceeds the mean over the cloud by more than stddev standard deviations "
                    "(StatisticalOutlierRemoval); radius: drop points with fewer than "
                    "min_neighbors others within radius (RadiusOutlierRemoval)."),
          kOutlierMethodNames);
    visit(self.k, parameter("k", "statistical: neighbors per point (PCL's tutorial: 50).")
                      .in("points")
                      .between(2, 10000));
    visit(self.stddev,
          parameter("stddev", "statistical: the threshold, in standard deviations above the mean.")
              .between(0, 100));
    visit(self.radius,
          parameter("radius", "radius: the search radius.").in("cloud units").above(0));
    visit(self.min_neighbors,
          parameter("min_neighbors", "radius: the fewest neighbors a kept point has.")
              .in("points")
              .between(1, 10000));
  }

  void validate() const;
};

/// The points PCL's StatisticalOutlierRemoval or RadiusOutlierRemoval keeps.
FilterSelection removeOutliers(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                               const OutlierRemovalParameters& parameters);

}  // namespace slipfit
