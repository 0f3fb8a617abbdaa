// Normal estimation on a generated 1,000,000-point cloud, k = 16, 2 threads: slipfit's classes and
// its pipeline stage against pcl::NormalEstimationOMP called directly, in the same run.
//
//   build/bench/bench_normals --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// bench/run_normals.sh runs each case in its own process to report peak memory as well.
#include "pcl_normals_peer.h"
#include "shapes.h"

#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/normal_estimation.h"
#include "slipfit/pipeline/progress.h"
#include "slipfit/pipeline/registry.h"

#include <benchmark/benchmark.h>
#include <pcl/search/kdtree.h>
#include <yaml-cpp/yaml.h>

#include <iostream>
#include <sstream>

namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;
constexpr int kThreads = 2;
constexpr int kK = 16;

/// slipfit::testing::millionPointScene, made once.
const Cloud::ConstPtr& scene() {
  static const Cloud::ConstPtr cloud =
      std::make_shared<Cloud>(slipfit::testing::millionPointScene());
  return cloud;
}

void BM_PclNormalEstimationOMP(benchmark::State& state) {
  slipfit::bench::timePclNormals(state, scene(), kK, kThreads, [] {
    return std::make_shared<pcl::search::KdTree<pcl::PointNormal>>(false);
  });
}

void BM_SlipfitNormalEstimation(benchmark::State& state) {
  slipfit::NormalParameters p;
  p.k = kK;
  p.threads = kThreads;
  for (auto _ : state) {
    slipfit::OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> ne;
    ne.setParameters(p);
    ne.setInputCloud(scene());
    pcl::PointCloud<pcl::Normal> out;
    ne.compute(out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene()->size()));
}

/// The pipeline's stage object (adapter included), own kNN search, as `slipfit run` executes it.
void BM_SlipfitNormalStage(benchmark::State& state) {
  using namespace slipfit::pipeline;
  const StageInfo* info = findStage("normal_estimation");
  std::ostringstream sink;
  Progress progress(false);
  RunContext context{progress, sink, kThreads, 1};
  for (auto _ : state) {
    state.PauseTiming();
    PointData data;
    data.cloud = std::make_shared<Cloud>(*scene());
    auto stage = info->make();
    OptionSet options;
    stage->declare(options);
    options.find("k")->parse(YAML::Load(std::to_string(kK)));
    options.find("orientation")->parse(YAML::Load("viewpoint"));
    stage->prepare();
    state.ResumeTiming();
    stage->run(data, context);
    benchmark::DoNotOptimize(data.cloud->data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene()->size()));
}

/// neighborhood_selection + normal_estimation sharing one search (the demo pipeline's path).
void BM_SlipfitNeighborhoodsThenNormals(benchmark::State& state) {
  slipfit::NeighborhoodParameters np;
  np.k = kK;
  np.threads = kThreads;
  slipfit::NormalParameters p;
  p.threads = kThreads;
  p.orientation = state.range(0) ? slipfit::NormalOrientation::consistent
                                 : slipfit::NormalOrientation::viewpoint;
  for (auto _ : state) {
    slipfit::NeighborhoodSelection<pcl::PointNormal> s;
    s.setParameters(np);
    s.setInputCloud(scene());
    auto hoods = std::make_shared<slipfit::Neighborhoods>();
    s.compute(*hoods);
    slipfit::OrientedNormalEstimation<pcl::PointNormal, pcl::Normal> ne;
    ne.setParameters(p);
    ne.setInputCloud(scene());
    ne.setNeighborhoods(hoods);
    pcl::PointCloud<pcl::Normal> out;
    ne.compute(out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(scene()->size()));
  state.SetLabel(state.range(0) ? "orientation=consistent" : "orientation=viewpoint");
}

BENCHMARK(BM_PclNormalEstimationOMP)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitNormalEstimation)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitNormalStage)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitNeighborhoodsThenNormals)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
