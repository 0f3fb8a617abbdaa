#pragma once
/// \file Per-point slippage over the neighborhoods shared by NeighborhoodSelection: the number of
/// slippable motions of each point's neighborhood, its type and a direction, as a registered PCL
/// point type.

#include "slipfit/neighborhoods/neighborhoods.h"
#include "slipfit/slippage/slippage.h"

#include <pcl/pcl_base.h>
#include <pcl/point_cloud.h>
#include <pcl/register_point_struct.h>

#include <cstdint>
#include <memory>

namespace slipfit {

/// Per-point slippage: `motions` (0–6), `slippage_type` (SlippageType as int), `axis_*` (plane:
/// normal; cylinder, cone, revolution, helix: axis; extrusion: direction; sphere: towards the
/// centre; else 0) and `gap`, the spectral gap λ_k/λ_{k−1} that decided the count (a confidence).
struct PointSlippage {
  std::int32_t motions = 0;
  std::int32_t slippage_type = 0;
  float axis_x = 0.0f;
  float axis_y = 0.0f;
  float axis_z = 0.0f;
  float gap = 0.0f;
};

/// PCL-style local analysis: setInputCloud() (a point type with normals), setNeighborhoods()
/// (required: one list per cloud point, e.g. from NeighborhoodSelection), optionally setIndices(),
/// then compute(). Output index-aligned with the indices; points whose neighborhood is degenerate
/// get slippage_type = degenerate and motions = 0.
template <typename PointT>
class LocalSlippage : public pcl::PCLBase<PointT> {
 public:
  using Ptr = std::shared_ptr<LocalSlippage<PointT>>;
  void setNeighborhoods(std::shared_ptr<const Neighborhoods> neighborhoods) {
    neighborhoods_ = std::move(neighborhoods);
  }
  void setOptions(const SlippageOptions& options) { options_ = options; }
  /// OpenMP threads; 0: all cores.
  void setNumberOfThreads(int threads) { threads_ = threads; }
  /// Throws DegenerateInputError without input or neighborhoods, or when sizes differ.
  void compute(pcl::PointCloud<PointSlippage>& output);

 protected:
  using pcl::PCLBase<PointT>::input_;
  using pcl::PCLBase<PointT>::indices_;

 private:
  std::shared_ptr<const Neighborhoods> neighborhoods_;
  SlippageOptions options_;
  int threads_ = 0;
};

}  // namespace slipfit

POINT_CLOUD_REGISTER_POINT_STRUCT(
    slipfit::PointSlippage,
    (std::int32_t, motions, motions)(std::int32_t, slippage_type, slippage_type)(
        float, axis_x, axis_x)(float, axis_y, axis_y)(float, axis_z, axis_z)(float, gap, gap))
