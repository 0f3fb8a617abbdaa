#pragma once
/// \file Neighborhood selection: kNN, radius, hybrid and adaptive (eigen-entropy) neighborhoods of
/// every point, through one kd-tree build and one neighbor search per point.

#include "slipfit/core/parameter_declaration.h"
#include "slipfit/neighborhoods/depth_quantization.h"
#include "slipfit/neighborhoods/neighborhoods.h"

#include <pcl/pcl_base.h>
#include <pcl/search/search.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace slipfit {

/// How a point's neighborhood is chosen.
enum class NeighborhoodMode {
  knn,      ///< the k nearest points
  radius,   ///< all points within a radius (optionally at most max_neighbors of the nearest)
  hybrid,   ///< the k nearest points, but none farther than the radius
  adaptive  ///< per point, the k in [k_min, k_max] with least eigen-entropy (Weinmann et al. 2015)
};

/// The one name table of NeighborhoodMode (used by the pipeline, the docs and error messages).
constexpr std::array<std::pair<NeighborhoodMode, std::string_view>, 4> kNeighborhoodModeNames{{
    {NeighborhoodMode::knn, "knn"},
    {NeighborhoodMode::radius, "radius"},
    {NeighborhoodMode::hybrid, "hybrid"},
    {NeighborhoodMode::adaptive, "adaptive"},
}};

/// Parameters of NeighborhoodSelection. Counts include the query point itself.
struct NeighborhoodParameters {
  NeighborhoodMode mode = NeighborhoodMode::knn;
  /// Neighbors per point in knn mode, and the cap in hybrid mode. Range [3, 10000].
  int k = 16;
  /// Search radius in the cloud's units, required in radius and hybrid modes. Range (0, ∞).
  std::optional<double> radius;
  /// In radius mode, keep at most this many of the nearest neighbors (unset: all). Range [3, ∞).
  std::optional<int> max_neighbors;
  /// Adaptive mode: the candidate sizes k_min, k_min + k_step, ..., k_max. 3 ≤ k_min ≤ k_max ≤
  /// 10000.
  int k_min = 8;
  int k_max = 48;
  int k_step = 2;
  /// knn mode: where one coordinate is recorded on a lattice of levels (the depth of a Kinect-like
  /// camera, see depth_quantization.h), a point whose k nearest lie within 1.5 local steps takes
  /// points up to 1.5 steps away instead — its k nearest and an evenly strided choice of the rest
  /// (of at most 64 k), 8 k in all — so that its neighborhood spans the levels and shows the
  /// surface, not a flat slice of it.
  bool span_quantization = true;
  /// knn mode, depth not on levels: where a sensor's noise across the surface is wider than the k
  /// nearest reach (they then lie in a slab of the noise, and their plane is not the surface's), a
  /// point takes the points within 4 σ of its region instead — its k nearest and an evenly
  /// strided choice of the rest, 8 k in all. σ is measured at sampled points, each widening its
  /// neighborhood until it holds the noise's slab; thin walls (two sheets) are told from noise.
  /// Only where at least a quarter of the samples are so noisy (a sensor's cloud).
  bool span_noise = true;
  /// OpenMP threads; 0 means as many as the machine has.
  int threads = 0;

  /// Each user-facing field with its one declaration (parameter_declaration.h).
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit(self.mode,
          parameter("mode",
                    "knn: the k nearest points; radius: all points within radius; hybrid: the k "
                    "nearest but none beyond radius; adaptive: per point the k in [k_min, k_max] "
                    "of least eigen-entropy (Weinmann et al. 2015)."),
          kNeighborhoodModeNames);
    visit(
        self.k,
        parameter("k", "Neighbors per point (knn), or the cap (hybrid); includes the point itself.")
            .in("points")
            .between(3, 10000));
    visit(
        self.radius,
        parameter("radius", "Search radius (radius and hybrid modes).").in("cloud units").above(0));
    visit(self.max_neighbors,
          parameter("max_neighbors",
                    "Radius mode: keep at most this many of the nearest (unset: "
                    "all).")
              .in("points")
              .between(3, 1e7));
    visit(self.k_min, parameter("k_min", "Adaptive mode: smallest candidate size.")
                          .in("points")
                          .between(3, 10000));
    visit(self.k_max, parameter("k_max", "Adaptive mode: largest candidate size.")
                          .in("points")
                          .between(3, 10000));
    visit(self.k_step, parameter("k_step", "Adaptive mode: step between candidate sizes.")
                           .in("points")
                           .between(1, 1000));
    visit(self.span_quantization,
          parameter("span_quantization",
                    "knn: where one coordinate is recorded on levels (Kinect-like depth), widen "
                    "the neighborhoods that lie within 1.5 local steps to every point within 1.5 "
                    "steps (at most 8 k), so that they span the levels."));
    visit(self.span_noise,
          parameter("span_noise",
                    "knn: where a sensor's noise across the surface is wider than the k nearest "
                    "reach (depth not on levels), widen those neighborhoods to 4 local σ (at most "
                    "8 k), so that they span the noise."));
  }

  /// Throws InvalidParameterError naming the field, its value and the broken constraint.
  void validate() const;
};

/// Counters of one NeighborhoodSelection::compute() call, for tests and reports.
struct NeighborhoodStatistics {
  std::size_t queries = 0;      ///< neighbor searches made (one per finite queried point)
  std::size_t tree_builds = 0;  ///< kd-tree builds made (0 when the given tree was already built,
                                ///< or the search is a GridSearch)
  std::size_t min_size = 0;     ///< smallest non-empty neighborhood
  std::size_t max_size = 0;     ///< largest neighborhood
  double mean_size = 0.0;       ///< mean size over queried finite points
  std::size_t skipped_nonfinite = 0;  ///< queried points with NaN/inf coordinates (empty lists)
  int quantized_axis = -1;     ///< the coordinate recorded on levels (QuantizedAxis::axis), or −1
  std::string quantized_name;  ///< its QuantizedAxis::name(), for reports
  double min_step = 0.0;       ///< its smallest and largest local step, cloud units
  double max_step = 0.0;
  std::size_t widened = 0;        ///< neighborhoods widened to span the levels
  std::size_t noise_widened = 0;  ///< neighborhoods widened to span the noise (span_noise)
  double noise_sigma_low = 0.0;   ///< 5th and 95th percentile of their σ, cloud units
  double noise_sigma_high = 0.0;
  bool pixel_grid = false;  ///< searched on a sensor's pixel grid (GridSearch), not a kd-tree
};

/// Computes the neighborhood of every (indexed) point of a cloud.
///
/// Usage follows PCL: setInputCloud(), optionally setIndices() and setSearchMethod(), then
/// compute(). The result has one list per cloud point (see Neighborhoods); only the indexed points
/// are queried. The search structure is built once on the whole input cloud.
template <typename PointT>
class NeighborhoodSelection : public pcl::PCLBase<PointT> {
 public:
  using Ptr = std::shared_ptr<NeighborhoodSelection<PointT>>;
  using ConstPtr = std::shared_ptr<const NeighborhoodSelection<PointT>>;
  using SearchPtr = typename pcl::search::Search<PointT>::Ptr;

  NeighborhoodSelection() = default;

  /// Checked when the work runs (one validation, PCL's initCompute convention).
  void setParameters(const NeighborhoodParameters& parameters) { parameters_ = parameters; }
  const NeighborhoodParameters& getParameters() const { return parameters_; }

  /// A search structure to use instead of a new NanoflannSearch (a kd-tree). If its input cloud is
  /// already the input cloud, it is not rebuilt.
  void setSearchMethod(const SearchPtr& search) { search_ = search; }
  SearchPtr getSearchMethod() const { return search_; }

  /// Computes the neighborhoods. Throws DegenerateInputError on an empty input or when fewer than
  /// two finite points exist.
  void compute(Neighborhoods& output);

  const NeighborhoodStatistics& statistics() const { return statistics_; }

 protected:
  using pcl::PCLBase<PointT>::input_;
  using pcl::PCLBase<PointT>::indices_;

 private:
  /// The checks of compute() on the input; the queried points (1 for each index).
  std::vector<char> checkInput();
  /// The search structure, built on the input unless it already is.
  void prepareSearch();
  /// knn with span_quantization: the coordinate recorded on levels, if any.
  QuantizedAxis detectLattice() const;
  /// Radius mode: the most entries one list may hold (the memory budget, or max_neighbors);
  /// throws InvalidParameterError when a look at 256 points shows the radius is too large.
  std::size_t radiusCap();
  /// The neighbors of point \a i into \a ind and \a d (sorted) by the mode; sets
  /// \a over_budget when a radius list reached \a radius_cap; counts a widened list.
  void query(std::size_t i, const QuantizedAxis& lattice, std::size_t radius_cap,
             Eigen::Matrix3Xf& local, pcl::Indices& ind, std::vector<float>& d, bool& over_budget,
             std::size_t& widened) const;
  /// The sizes of \a output into statistics_.
  void summarise(const Neighborhoods& output, std::size_t queries);
  /// Throws DegenerateInputError with \a failure, a search's error, unless it is empty.
  void throwSearchFailure(const std::string& failure);
  /// The lists of the \a queried points, searched a chunk of points at a time in cloud order and
  /// appended in that order (every mode).
  void searchInCloudOrder(const std::vector<char>& queried, const QuantizedAxis& lattice,
                          std::size_t radius_cap, Neighborhoods& output);
  /// knn lists of one known size, searched along spatialOrder() and written in place: on a cloud
  /// in no spatial order the kd-tree walks warm memory (THEORY §1).
  void searchInSpatialOrder(const std::vector<char>& queried, Neighborhoods& output);
  /// knn with span_noise: the lists of the points whose noise is wider than their k nearest,
  /// widened to span it (noise_span.hpp).
  void spanNoise(const std::vector<char>& queried, Neighborhoods& output);
  /// The σ across the surface at each of \a samples (0: not noise-dominated), from the knn lists
  /// \a output of the \a finite listed points.
  std::vector<double> sampledNoise(const std::vector<pcl::index_t>& samples,
                                   const Neighborhoods& output, std::size_t finite) const;

  NeighborhoodParameters parameters_;
  SearchPtr search_;
  NeighborhoodStatistics statistics_;
};

}  // namespace slipfit
