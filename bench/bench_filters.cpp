// The filter stages (crop, voxel_grid, outlier_removal) as `slipfit run` executes them (adapter and
// the removal of the dropped points from every per-point array included) against the PCL filter
// they wrap called directly (selecting indices, as the stage does, then copying the kept points),
// on a generated 1,000,000-point cloud, in the same run.
//
//   build/bench/bench_filters --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "shapes.h"

#include "slipfit/pipeline/progress.h"
#include "slipfit/pipeline/registry.h"

#include <benchmark/benchmark.h>
#include <pcl/common/io.h>
#include <pcl/filters/passthrough.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/uniform_sampling.h>
#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointNormal>;

/// slipfit::testing::millionPointScene, made once.
const Cloud::ConstPtr& scene() {
  static const Cloud::ConstPtr cloud =
      std::make_shared<Cloud>(slipfit::testing::millionPointScene());
  return cloud;
}

/// The stage \a type with \a options (YAML values), run on a copy of the scene.
void runStage(benchmark::State& state, const std::string& type,
              const std::vector<std::pair<std::string, std::string>>& options) {
  using namespace slipfit::pipeline;
  const StageInfo* info = findStage(type);
  std::ostringstream sink;
  Progress progress(false);
  RunContext context{progress, sink, 1, 1};
  std::size_t kept = 0;
  PointData data;  // the last output is released untimed, as runPcl's
  for (auto _ : state) {
    state.PauseTiming();
    data = PointData{};
    data.cloud = std::make_shared<Cloud>(*scene());
    auto stage = info->make();
    OptionSet set;
    stage->declare(set);
    for (const auto& [name, value] : options)
      set.find(name)->parse(YAML::Load(value));
    stage->prepare();
    state.ResumeTiming();
    stage->run(data, context);
    kept = data.size();
    benchmark::DoNotOptimize(data.cloud->data());
  }
  state.counters["kept"] = static_cast<double>(kept);
}

/// PCL's filter selecting indices, then the kept points copied out (into a new cloud: the input
/// is the caller's). Each side's output of the iteration before is released with the clock
/// stopped, and the stage's input copy is made with it stopped. \a make returns a configured
/// filter: one per cloud, as a user filtering a cloud (and the stage) calls it. A filter object
/// kept across iterations would keep its "all points" index list of the last cloud (PCLBase's
/// fake indices) and skip building it: BM_PclPassThroughReused measures that too.
template <typename Make>
void runPcl(benchmark::State& state, Make make) {
  std::size_t kept = 0;
  Cloud out;  // the last output is released untimed, as runStage's
  for (auto _ : state) {
    state.PauseTiming();
    out = Cloud{};
    state.ResumeTiming();
    decltype(auto) filter = make();
    filter.setInputCloud(scene());
    pcl::Indices indices;
    filter.filter(indices);
    pcl::copyPointCloud(*scene(), indices, out);
    kept = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["kept"] = static_cast<double>(kept);
}

pcl::PassThrough<pcl::PointNormal> passThrough() {
  pcl::PassThrough<pcl::PointNormal> f;
  f.setFilterFieldName("z");
  f.setFilterLimits(-0.5f, 0.5f);
  return f;
}
void BM_PclPassThrough(benchmark::State& state) {
  runPcl(state, passThrough);
}
void BM_PclPassThroughReused(benchmark::State& state) {
  auto f = passThrough();
  runPcl(
      state, [&f]() -> auto& { return f; });
}
void BM_SlipfitCrop(benchmark::State& state) {
  runStage(state, "crop", {{"field", "z"}, {"min", "-0.5"}, {"max", "0.5"}});
}

void BM_PclStatisticalOutlierRemoval(benchmark::State& state) {
  runPcl(state, [] {
    pcl::StatisticalOutlierRemoval<pcl::PointNormal> f;
    f.setMeanK(20);
    f.setStddevMulThresh(2.0);
    return f;
  });
}
void BM_SlipfitOutlierRemoval(benchmark::State& state) {
  runStage(state, "outlier_removal", {{"k", "20"}, {"stddev", "2"}});
}

void BM_PclUniformSampling(benchmark::State& state) {
  std::size_t kept = 0;
  Cloud out;  // released untimed, as in runPcl
  for (auto _ : state) {
    state.PauseTiming();
    out = Cloud{};
    state.ResumeTiming();
    pcl::UniformSampling<pcl::PointNormal> f(true);
    f.setInputCloud(scene());
    f.setRadiusSearch(0.02);
    f.filter(out);
    kept = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["kept"] = static_cast<double>(kept);
}
void BM_SlipfitVoxelGrid(benchmark::State& state) {
  runStage(state, "voxel_grid", {{"leaf", "0.02"}});
}

BENCHMARK(BM_PclPassThrough)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclPassThroughReused)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitCrop)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclStatisticalOutlierRemoval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitOutlierRemoval)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PclUniformSampling)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SlipfitVoxelGrid)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
