#include "slipfit/filters/point_filters.h"

#include "slipfit/core/exceptions.h"

#include <pcl/common/common.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/passthrough.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/uniform_sampling.h>
#include <pcl/filters/voxel_grid.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>

namespace slipfit {

namespace {

[[noreturn]] void rejectCrop(const std::string& what) {
  throw InvalidParameterError("crop: " + what);
}

/// The indices of [0, n) that \a in does not hold, ascending.
pcl::Indices complement(const pcl::Indices& in, std::size_t n) {
  std::vector<char> inside(n, 0);
  for (const auto i : in)
    inside[static_cast<std::size_t>(i)] = 1;
  pcl::Indices out;
  for (std::size_t i = 0; i < n; ++i)
    if (!inside[i])
      out.push_back(static_cast<pcl::index_t>(i));
  return out;
}

void sortAscending(pcl::Indices& indices) {
  std::sort(indices.begin(), indices.end());
}

}  // namespace

void CropParameters::validate() const {
  validateDeclared(*this, "crop");
  const bool pass = field != CropField::none;
  if (pass != (min || max))
    rejectCrop(pass ? "field needs min and/or max" : "min and max need field (x, y or z)");
  if ((min && !std::isfinite(*min)) || (max && !std::isfinite(*max)))
    rejectCrop("min and max must be finite");
  if (min && max && !(*min <= *max))
    rejectCrop("min must not exceed max");
  if (box_min.has_value() != box_max.has_value())
    rejectCrop("box_min and box_max go together");
  if (box_min && !(box_min->allFinite() && box_max->allFinite()))
    rejectCrop("box_min and box_max must be finite");
  if (box_min && !(box_min->array() < box_max->array()).all())
    rejectCrop("box_min must be below box_max on every axis");
  if (!pass && !box_min)
    rejectCrop("give field with min/max, or box_min and box_max");
}

namespace {

/// \a p as "(x, y, z)" with every digit a georeferenced coordinate needs (5400000, not 5.4e+06).
std::string corner(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s << std::setprecision(12) << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

}  // namespace

FilterSelection crop(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                     const CropParameters& p, const Eigen::Vector3d& shift) {
  p.validate();
  FilterSelection out;
  std::ostringstream why;
  const bool pass = p.field != CropField::none;
  if (pass) {
    pcl::PassThrough<pcl::PointNormal> filter;
    filter.setInputCloud(cloud);
    const std::string name(kCropFieldNames[static_cast<std::size_t>(p.field)].second);
    filter.setFilterFieldName(name);
    const double lo = p.min.value_or(-std::numeric_limits<float>::max());
    const double hi = p.max.value_or(std::numeric_limits<float>::max());
    const double t = shift[static_cast<int>(p.field) - 1];
    filter.setFilterLimits(static_cast<float>(lo - t), static_cast<float>(hi - t));
    filter.setNegative(p.negative && !p.box_min);
    filter.filter(out.kept);
    // A one-sided limit says which side, not the float range's end (-3.40282e+38).
    why << std::setprecision(12);
    if (p.min && p.max)
      why << name << " in [" << lo << ", " << hi << "]";
    else if (p.min)
      why << name << " >= " << lo;
    else
      why << name << " <= " << hi;
  }
  if (p.box_min) {
    pcl::CropBox<pcl::PointNormal> box;
    box.setInputCloud(cloud);
    if (pass)
      box.setIndices(pcl::make_shared<pcl::Indices>(out.kept));
    const Eigen::Vector3f low = (*p.box_min - shift).cast<float>();
    const Eigen::Vector3f high = (*p.box_max - shift).cast<float>();
    box.setMin(Eigen::Vector4f(low.x(), low.y(), low.z(), 1.0f));
    box.setMax(Eigen::Vector4f(high.x(), high.y(), high.z(), 1.0f));
    box.setNegative(p.negative && !pass);
    box.filter(out.kept);
    why << (pass ? ", " : "") << "inside the box " << corner(*p.box_min) << " – "
        << corner(*p.box_max);
  }
  if (p.negative && pass && p.box_min)
    out.kept = complement(out.kept, cloud->size());
  sortAscending(out.kept);
  out.why = (p.negative ? "kept outside: " : "kept ") + why.str();
  return out;
}

void VoxelGridParameters::validate() const {
  validateDeclared(*this, "voxel_grid");
}

namespace {

/// PCL's grids index voxels with 32-bit integers and, when they would overflow, warn and return
/// the cloud unchanged: say so instead.
void checkGrid(const pcl::PointCloud<pcl::PointNormal>& cloud, double leaf) {
  pcl::PointNormal lo, hi;
  pcl::getMinMax3D(cloud, lo, hi);
  double voxels = 1.0;
  for (int a = 0; a < 3; ++a)
    voxels *= std::floor((hi.getVector3fMap()[a] - lo.getVector3fMap()[a]) / leaf) + 1.0;
  if (voxels > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    throw DegenerateInputError("leaf " + std::to_string(leaf) + " gives " + std::to_string(voxels) +
                               " voxels over the cloud's extent, more than PCL's grid can index "
                               "(2^31); use a larger leaf");
}

pcl::Indices uniformSample(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, double leaf) {
  pcl::UniformSampling<pcl::PointNormal> sampling(true);
  sampling.setInputCloud(cloud);
  sampling.setRadiusSearch(leaf);
  pcl::PointCloud<pcl::PointNormal> kept_points;
  sampling.filter(kept_points);
  std::vector<char> removed(cloud->size(), 0);
  for (const auto i : *sampling.getRemovedIndices())
    removed[static_cast<std::size_t>(i)] = 1;
  pcl::Indices kept;
  for (std::size_t i = 0; i < cloud->size(); ++i)
    if (!removed[i])
      kept.push_back(static_cast<pcl::index_t>(i));
  return kept;
}

/// Each voxel's input point nearest the voxel's centroid stands for it, moved to the centroid.
pcl::Indices centroidSample(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, double leaf,
                            std::vector<Eigen::Vector3f>& at) {
  pcl::VoxelGrid<pcl::PointNormal> grid;
  grid.setInputCloud(cloud);
  const auto edge = static_cast<float>(leaf);
  grid.setLeafSize(edge, edge, edge);
  grid.setSaveLeafLayout(true);
  pcl::PointCloud<pcl::PointNormal> centroids;
  grid.filter(centroids);
  const std::size_t m = centroids.size();
  std::vector<pcl::index_t> nearest(m, -1);
  std::vector<float> best(m, std::numeric_limits<float>::max());
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const int v = grid.getCentroidIndex((*cloud)[i]);
    if (v < 0 || static_cast<std::size_t>(v) >= m)
      continue;
    const auto u = static_cast<std::size_t>(v);
    const float d = ((*cloud)[i].getVector3fMap() - centroids[u].getVector3fMap()).squaredNorm();
    if (d < best[u]) {
      best[u] = d;
      nearest[u] = static_cast<pcl::index_t>(i);
    }
  }
  std::vector<int> voxel(cloud->size(), -1);
  pcl::Indices kept;
  for (std::size_t v = 0; v < m; ++v)
    if (nearest[v] >= 0) {
      kept.push_back(nearest[v]);
      voxel[static_cast<std::size_t>(nearest[v])] = static_cast<int>(v);
    }
  sortAscending(kept);
  at.clear();
  at.reserve(kept.size());
  for (const auto i : kept)
    at.push_back(
        centroids[static_cast<std::size_t>(voxel[static_cast<std::size_t>(i)])].getVector3fMap());
  return kept;
}

}  // namespace

FilterSelection voxelGrid(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                          const VoxelGridParameters& p, std::vector<Eigen::Vector3f>& centroids) {
  p.validate();
  checkGrid(*cloud, p.leaf);
  FilterSelection out;
  out.why = "one per voxel of " + std::to_string(p.leaf) + ", " +
            std::string(kVoxelMethodNames[static_cast<std::size_t>(p.method)].second);
  centroids.clear();
  out.kept = p.method == VoxelMethod::uniform ? uniformSample(cloud, p.leaf)
                                              : centroidSample(cloud, p.leaf, centroids);
  return out;
}

void OutlierRemovalParameters::validate() const {
  validateDeclared(*this, "outlier_removal");
  if ((method == OutlierMethod::radius) != radius.has_value())
    throw InvalidParameterError(method == OutlierMethod::radius
                                    ? "outlier_removal: method radius needs radius"
                                    : "outlier_removal: radius is for method radius");
}

FilterSelection removeOutliers(const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud,
                               const OutlierRemovalParameters& p) {
  p.validate();
  FilterSelection out;
  std::ostringstream why;
  if (p.method == OutlierMethod::statistical) {
    pcl::StatisticalOutlierRemoval<pcl::PointNormal> sor;
    sor.setInputCloud(cloud);
    sor.setMeanK(p.k);
    sor.setStddevMulThresh(p.stddev);
    sor.filter(out.kept);
    why << "mean distance to " << p.k << " neighbors within " << p.stddev
        << " standard deviations of the cloud's";
  } else {
    pcl::RadiusOutlierRemoval<pcl::PointNormal> ror;
    ror.setInputCloud(cloud);
    ror.setRadiusSearch(*p.radius);
    ror.setMinNeighborsInRadius(p.min_neighbors);
    ror.filter(out.kept);
    why << "at least " << p.min_neighbors << " neighbors within " << *p.radius;
  }
  sortAscending(out.kept);
  out.why = why.str();
  return out;
}

}  // namespace slipfit
