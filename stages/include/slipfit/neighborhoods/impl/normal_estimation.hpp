#pragma once

#include <Eigen/Eigenvalues>

#include "slipfit/core/cloud_maps.h"
#include "slipfit/core/exceptions.h"
#include "slipfit/neighborhoods/nanoflann_search.h"
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/neighborhoods/precomputed_search.h"

#include <pcl/features/normal_3d_omp.h>

#include <algorithm>
#include <limits>
#include <string>

namespace slipfit {

/// True when the finite indexed points span no plane: the middle eigenvalue of their covariance
/// vanishes against the largest (a line, or a single repeated point).
template <typename PointT>
bool collinear(const pcl::PointCloud<PointT>& cloud, const pcl::Indices& indices) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t m = 0;
  for (pcl::index_t i : indices)
    if (cloud[static_cast<std::size_t>(i)].getVector3fMap().allFinite()) {
      mean += cloud[static_cast<std::size_t>(i)].getVector3fMap().template cast<double>();
      ++m;
    }
  if (m < 3)
    return false;  // too few points is reported by the estimation itself
  mean /= static_cast<double>(m);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (pcl::index_t i : indices) {
    const Eigen::Vector3f p = cloud[static_cast<std::size_t>(i)].getVector3fMap();
    if (p.allFinite()) {
      const Eigen::Vector3d d = p.template cast<double>() - mean;
      cov += d * d.transpose();
    }
  }
  const Eigen::Vector3d l =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
  return !(l(1) > 1e-12 * l(2));
}

template <typename PointInT, typename PointOutT>
void OrientedNormalEstimation<PointInT, PointOutT>::compute(pcl::PointCloud<PointOutT>& output) {
  parameters_.validate();
  if (!input_ || input_->empty())
    throw DegenerateInputError("normal estimation: the input cloud is empty");
  if (!this->initCompute())
    throw DegenerateInputError("normal estimation: the indices do not fit the input cloud");
  statistics_ = NormalStatistics{};
  const NormalParameters& par = parameters_;
  const std::size_t n = input_->size();

  if (collinear(*input_, *indices_)) {
    this->deinitCompute();
    throw DegenerateInputError(
        "normal estimation: the points are collinear (or all identical): no surface, normals are "
        "undefined");
  }
  std::shared_ptr<const Neighborhoods> hoods = neighborhoods_;
  if (hoods && hoods->size() != n) {
    this->deinitCompute();
    throw DegenerateInputError("normal estimation: the neighborhoods were computed for " +
                               std::to_string(hoods->size()) + " points, the cloud has " +
                               std::to_string(n));
  }
  if (par.orientation == NormalOrientation::reference &&
      (!reference_ || static_cast<std::size_t>(reference_->cols()) != n)) {
    this->deinitCompute();
    throw DegenerateInputError(
        "normal estimation: reference orientation needs one reference normal per cloud point");
  }
  if (!hoods && par.orientation == NormalOrientation::consistent) {
    // The orientation graph needs the neighborhoods anyway: search once and share them.
    NeighborhoodSelection<PointInT> selection;
    NeighborhoodParameters np;
    np.mode = par.radius ? NeighborhoodMode::radius : NeighborhoodMode::knn;
    np.k = par.k;
    np.radius = par.radius;
    np.threads = par.threads;
    selection.setParameters(np);
    selection.setInputCloud(input_);
    selection.setIndices(indices_);
    if (search_)
      selection.setSearchMethod(search_);
    auto computed = std::make_shared<Neighborhoods>();
    selection.compute(*computed);
    hoods = computed;
  }

  pcl::NormalEstimationOMP<PointInT, PointOutT> ne(static_cast<unsigned>(par.threads));
  ne.setInputCloud(input_);
  ne.setIndices(indices_);
  if (hoods) {
    ne.setSearchMethod(std::make_shared<PrecomputedSearch<PointInT>>(hoods));
    ne.setKSearch(static_cast<int>(std::max<std::size_t>(hoods->maxSize(), 1)));
    statistics_.reused_neighborhoods = neighborhoods_ != nullptr;
  } else {
    // PCL's default would be its FLANN kd-tree; the neighborhoods' own is a third of its time.
    ne.setSearchMethod(search_ ? search_ : std::make_shared<NanoflannSearch<PointInT>>());
    if (par.radius)
      ne.setRadiusSearch(*par.radius);
    else
      ne.setKSearch(par.k);
  }
  const Eigen::Vector3f vp = par.orientation == NormalOrientation::sensor
                                 ? Eigen::Vector3f(input_->sensor_origin_.template head<3>())
                                 : par.viewpoint.value_or(Eigen::Vector3f::Zero());
  ne.setViewPoint(vp.x(), vp.y(), vp.z());
  ne.compute(output);
  if (output.size() != indices_->size()) {
    this->deinitCompute();
    throw DegenerateInputError("normal estimation: pcl::NormalEstimationOMP produced no output");
  }

  if (!output.empty()) {
    Coords3Map out_normals = normals(output);
    if (par.orientation == NormalOrientation::reference) {
      Eigen::Matrix3Xf ref(3, static_cast<Eigen::Index>(indices_->size()));
      for (std::size_t j = 0; j < indices_->size(); ++j)
        ref.col(j) = reference_->col((*indices_)[j]);
      statistics_.flipped = orientLikeReference(
          out_normals, ConstCoords3Map(ref.data(), 3, ref.cols(), Eigen::OuterStride<>(3)));
    } else if (par.orientation == NormalOrientation::consistent) {
      // The graph is indexed by cloud point: scatter the output's normals to cloud order.
      Eigen::Matrix3Xf full = Eigen::Matrix3Xf::Constant(3, static_cast<Eigen::Index>(n),
                                                         std::numeric_limits<float>::quiet_NaN());
      for (std::size_t j = 0; j < indices_->size(); ++j)
        full.col((*indices_)[j]) = out_normals.col(j);
      const auto report = orientConsistently(
          coordinates(*input_), Coords3Map(full.data(), 3, full.cols(), Eigen::OuterStride<>(3)),
          *hoods, par.viewpoint);
      for (std::size_t j = 0; j < indices_->size(); ++j)
        out_normals.col(j) = full.col((*indices_)[j]);
      statistics_.flipped = report.flipped;
      statistics_.components = report.components;
    }
    for (Eigen::Index j = 0; j < out_normals.cols(); ++j) {
      if (out_normals.col(j).allFinite())
        ++statistics_.estimated;
      else
        ++statistics_.failed;
    }
  }
  this->deinitCompute();
}

}  // namespace slipfit
