#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/fitting/primitive_fitting.h"

#include <string>

namespace slipfit {

template <typename PointT, typename NormalT>
FitResult PrimitiveFitting<PointT, NormalT>::fit() {
  if (!input_ || input_->empty())
    throw DegenerateInputError("primitive fitting: the input cloud is empty");
  if (!this->initCompute())
    throw DegenerateInputError("primitive fitting: the indices do not fit the input cloud");
  const bool need_normals =
      !type_ || *type_ == PrimitiveType::cylinder || *type_ == PrimitiveType::cone;
  if (normals_ && normals_->size() != input_->size()) {
    this->deinitCompute();
    throw InvalidParameterError("primitive fitting: " + std::to_string(normals_->size()) +
                                " normals for " + std::to_string(input_->size()) + " points");
  }
  if (weights_ && weights_->size() != input_->size()) {
    this->deinitCompute();
    throw InvalidParameterError("primitive fitting: " + std::to_string(weights_->size()) +
                                " weights for " + std::to_string(input_->size()) + " points");
  }
  if (need_normals && type_ && !normals_) {
    this->deinitCompute();
    throw InvalidParameterError("primitive fitting: a " + std::string(primitiveTypeName(*type_)) +
                                " needs normals (setInputNormals)");
  }
  const auto m = static_cast<Eigen::Index>(indices_->size());
  Eigen::Matrix3Xd points(3, m), normals(3, normals_ ? m : 0);
  Eigen::VectorXd weights(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const auto i = (*indices_)[static_cast<std::size_t>(j)];
    points.col(j) = (*input_)[i].getVector3fMap().template cast<double>();
    if (normals_)
      normals.col(j) = (*normals_)[i].getNormalVector3fMap().template cast<double>();
    weights[j] = weights_ ? static_cast<double>((*weights_)[static_cast<std::size_t>(i)]) : 1.0;
  }
  this->deinitCompute();
  const FitResult r = type_ ? fitPrimitive(*type_, points, normals, weights, options_)
                            : fitAuto(points, normals, weights, options_);
  if (!r.ok())
    throw DegenerateInputError(r.reason);
  return r;
}

}  // namespace slipfit
