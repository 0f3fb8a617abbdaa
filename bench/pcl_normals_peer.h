#pragma once
/// \file The peer every normals and slippage benchmark measures against in the same run: PCL's
/// NormalEstimationOMP with k neighbours, over the search the benchmark gives it.

#include <benchmark/benchmark.h>
#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>

namespace slipfit::bench {

/// Times NormalEstimationOMP on \a cloud; \a make_search() returns the search (a fresh kd-tree,
/// or shared neighborhoods) built inside the timed loop, as a caller of PCL would.
template <typename MakeSearch>
void timePclNormals(benchmark::State& state,
                    const pcl::PointCloud<pcl::PointNormal>::ConstPtr& cloud, int k, int threads,
                    MakeSearch make_search) {
  for (auto _ : state) {
    pcl::NormalEstimationOMP<pcl::PointNormal, pcl::Normal> ne(threads);
    ne.setInputCloud(cloud);
    ne.setSearchMethod(make_search());
    ne.setKSearch(k);
    pcl::PointCloud<pcl::Normal> out;
    ne.compute(out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(cloud->size()));
}

}  // namespace slipfit::bench
