// Per-point slippage on 1,000,000 points with k = 20 shared neighborhoods, 2 threads, against
// pcl::NormalEstimationOMP with the same k in the same run (a 3 × 3 problem per point where
// slippage solves a 6 × 6 one): once on the same shared neighborhoods, once with PCL's own search.
// Also the whole-cloud spectrum at 10^4..10^6 points (linear in N), and the whole-cloud verdict
// (classifyShape: the spectrum, the surface noise and a refined fit of every type) at 10^4 and
// 10^5 points.
#include "pcl_normals_peer.h"
#include "shapes.h"

#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/precomputed_search.h"
#include "slipfit/slippage/local_slippage.h"
#include "slipfit/slippage/shape_classification.h"
#include "slipfit/slippage/slippage.h"

#include <benchmark/benchmark.h>
#include <pcl/search/kdtree.h>

namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;
constexpr int kThreads = 2;
constexpr int kK = 20;

const Cloud::ConstPtr& scene() {
  static const Cloud::ConstPtr cloud = [] {
    using namespace slipfit::testing;
    auto c = std::make_shared<Cloud>(samplePlane(500000, -3, 3, -3, 3, 0, 1));
    append(*c, sampleSphere(250000, Eigen::Vector3f(-1, 1, 1), 0.8f, 2));
    append(*c, sampleCylinder(250000, Eigen::Vector3f(1.2f, -1, 0), 0.4f, 2.0f, 3));
    return c;
  }();
  return cloud;
}

const std::shared_ptr<const slipfit::Neighborhoods>& hoods() {
  static const std::shared_ptr<const slipfit::Neighborhoods> h = [] {
    slipfit::NeighborhoodSelection<pcl::PointNormal> s;
    slipfit::NeighborhoodParameters p;
    p.k = kK;
    p.threads = kThreads;
    s.setParameters(p);
    s.setInputCloud(scene());
    auto out = std::make_shared<slipfit::Neighborhoods>();
    s.compute(*out);
    return std::shared_ptr<const slipfit::Neighborhoods>(out);
  }();
  return h;
}

void BM_LocalSlippage(benchmark::State& state) {
  hoods();
  for (auto _ : state) {
    slipfit::LocalSlippage<pcl::PointNormal> local;
    local.setInputCloud(scene());
    local.setNeighborhoods(hoods());
    local.setNumberOfThreads(kThreads);
    pcl::PointCloud<slipfit::PointSlippage> out;
    local.compute(out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene()->size()));
}

void BM_PclNormalsSharedNeighborhoods(benchmark::State& state) {
  hoods();
  slipfit::bench::timePclNormals(state, scene(), kK, kThreads, [] {
    return std::make_shared<slipfit::PrecomputedSearch<pcl::PointNormal>>(hoods());
  });
}

void BM_PclNormalsOwnSearch(benchmark::State& state) {
  slipfit::bench::timePclNormals(state, scene(), kK, kThreads, [] {
    return std::make_shared<pcl::search::KdTree<pcl::PointNormal>>(false);
  });
}

void BM_WholeCloudSlippage(benchmark::State& state) {
  const auto n = state.range(0);
  Eigen::Matrix3Xd x(3, n), nn(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& p = (*scene())[static_cast<std::size_t>(500000 + i % 250000)];  // the sphere
    x.col(i) = p.getVector3fMap().cast<double>();
    nn.col(i) = p.getNormalVector3fMap().cast<double>();
  }
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  for (auto _ : state)
    benchmark::DoNotOptimize(slipfit::analyzeSlippage(x, nn, w).motions);
  state.SetItemsProcessed(state.iterations() * n);
}

void BM_WholeCloudClassification(benchmark::State& state) {
  const auto n = state.range(0);
  Eigen::Matrix3Xd x(3, n), nn(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& p = (*scene())[static_cast<std::size_t>(750000 + i % 250000)];  // the cylinder
    x.col(i) = p.getVector3fMap().cast<double>();
    nn.col(i) = p.getNormalVector3fMap().cast<double>();
  }
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  for (auto _ : state)
    benchmark::DoNotOptimize(slipfit::classifyShape(x, nn, w).verdict.motions);
  state.SetItemsProcessed(state.iterations() * n);
}

BENCHMARK(BM_PclNormalsOwnSearch)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclNormalsSharedNeighborhoods)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_LocalSlippage)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_WholeCloudSlippage)
    ->Arg(10000)
    ->Arg(100000)
    ->Arg(1000000)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeCloudClassification)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
