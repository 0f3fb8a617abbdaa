#pragma once

#include "slipfit/core/exceptions.h"
#include "slipfit/core/threads.h"
#include "slipfit/slippage/local_slippage.h"

#include <omp.h>

#include <string>

namespace slipfit {

/// Direction reported for a point: see PointSlippage.
Eigen::Vector3d slippageDirection(const SlippageResult& r, const Eigen::Vector3d& point);

template <typename PointT>
void LocalSlippage<PointT>::compute(pcl::PointCloud<PointSlippage>& output) {
  if (!input_ || input_->empty())
    throw DegenerateInputError("local slippage: the input cloud is empty");
  if (!neighborhoods_ || neighborhoods_->size() != input_->size())
    throw DegenerateInputError(
        "local slippage: needs one neighborhood per cloud point (setNeighborhoods)");
  if (!this->initCompute())
    throw DegenerateInputError("local slippage: the indices do not fit the input cloud");
  const auto& cloud = *input_;
  const auto& hoods = *neighborhoods_;
  const auto m = static_cast<std::ptrdiff_t>(indices_->size());
  output.resize(static_cast<std::size_t>(m));
  output.width = static_cast<std::uint32_t>(m);
  output.height = 1;
  output.is_dense = true;
  const SlippageOptions options = options_;
  const int workers = resolveThreads(threads_);
#pragma omp parallel num_threads(workers)
  {
    Eigen::Matrix3Xd x, n;
    Eigen::VectorXd w;
#pragma omp for schedule(dynamic, 512)
    for (std::ptrdiff_t j = 0; j < m; ++j) {
      const auto i = static_cast<std::size_t>((*indices_)[static_cast<std::size_t>(j)]);
      const NeighborView v = hoods[i];
      const auto k = static_cast<Eigen::Index>(v.size());
      x.resize(3, k);
      n.resize(3, k);
      w.setOnes(k);
      for (Eigen::Index a = 0; a < k; ++a) {
        const auto& q = cloud[static_cast<std::size_t>(v[static_cast<std::size_t>(a)])];
        x.col(a) = q.getVector3fMap().template cast<double>();
        n.col(a) = q.getNormalVector3fMap().template cast<double>();
      }
      const SlippageResult r = analyzeSlippage(x, n, w, options);
      PointSlippage& out = output[static_cast<std::size_t>(j)];
      out.motions = r.type == SlippageType::degenerate ? 0 : r.motions;
      out.slippage_type = static_cast<std::int32_t>(r.type);
      const Eigen::Vector3f d =
          slippageDirection(r, cloud[i].getVector3fMap().template cast<double>())
              .template cast<float>();
      out.axis_x = d.x();
      out.axis_y = d.y();
      out.axis_z = d.z();
      out.gap = r.motions > 0 && r.motions < 6
                    ? static_cast<float>(std::max(r.spectrum(r.motions), 1e-6) /
                                         std::max(r.spectrum(r.motions - 1), 1e-6))
                    : 0.0f;
    }
  }
  this->deinitCompute();
}

}  // namespace slipfit
