#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/fitting/labelled_fitting.h"

#include <string>

namespace slipfit {

template <typename PointT, typename NormalT>
void LabelledFitting<PointT, NormalT>::compute(LabelledFits& fits) {
  parameters_.validate();
  if (!input_ || input_->empty())
    throw DegenerateInputError("labelled fitting: the input cloud is empty");
  const std::size_t n = input_->size();
  const auto mismatch = [&](const char* what, std::size_t count) {
    return InvalidParameterError("labelled fitting: " + std::to_string(count) + " " + what +
                                 " for " + std::to_string(n) + " points");
  };
  if (normals_ && normals_->size() != n)
    throw mismatch("normals", normals_->size());
  if (weights_ && weights_->size() != n)
    throw mismatch("weights", weights_->size());
  if (labels_ && labels_->size() != n)
    throw mismatch("labels", labels_->size());
  if (!this->initCompute())
    throw DegenerateInputError("labelled fitting: the indices do not fit the input cloud");
  const std::size_t m = indices_->size();
  Eigen::Matrix3Xd points(3, static_cast<Eigen::Index>(m));
  Eigen::Matrix3Xd normals(3, normals_ ? static_cast<Eigen::Index>(m) : 0);
  std::vector<double> weights(m, 1.0), labels(labels_ ? m : 0);
  for (std::size_t j = 0; j < m; ++j) {
    const auto i = static_cast<std::size_t>((*indices_)[j]);
    const auto col = static_cast<Eigen::Index>(j);
    points.col(col) = (*input_)[i].getVector3fMap().template cast<double>();
    if (normals_)
      normals.col(col) = (*normals_)[i].getNormalVector3fMap().template cast<double>();
    if (weights_)
      weights[j] = (*weights_)[i];
    if (labels_)
      labels[j] = (*labels_)[i];
  }
  const bool whole = this->fake_indices_;
  std::vector<pcl::index_t> subset;
  if (!whole)
    subset.assign(indices_->begin(), indices_->end());
  this->deinitCompute();
  fits = fitLabelled(points, normals, weights, labels, parameters_, seed_);
  if (!whole) {  // distances back to cloud indices
    std::vector<float> distance(n, -1.0f);
    for (std::size_t j = 0; j < m; ++j)
      distance[static_cast<std::size_t>(subset[j])] = fits.distance[j];
    fits.distance = std::move(distance);
  }
}

}  // namespace slipfit
