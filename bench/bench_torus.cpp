// Torus sampling and meshing cost (issue 3): samples per second at 10^4, 10^5, 10^6 (linear
// scaling), the Bézier evaluation against the closed-form trigonometric formula as the peer, and
// the stitched OpenMesh mesh at 100², 316² and 1000² vertices.
//
//   build/bench/bench_torus --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "slipfit/sampling/random_vector.h"
#include "slipfit/sampling/torus_sampler.h"
#include "slipfit/surfaces/torus_mesh.h"

#include <benchmark/benchmark.h>

#include <random>

namespace {

void BM_TorusSampleArea(benchmark::State& state) {
  slipfit::TorusSamplingParameters p;
  p.shape = {1.0, 0.3};
  p.points = static_cast<std::size_t>(state.range(0));
  slipfit::TorusSampler sampler;
  sampler.setParameters(p);
  for (auto _ : state) {
    pcl::PointCloud<pcl::PointNormal> cloud;
    sampler.sample(cloud);
    benchmark::DoNotOptimize(cloud.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

/// Bézier (de Casteljau, with derivatives and normal) at random angles.
void BM_TorusBezierEvaluate(benchmark::State& state) {
  const slipfit::TorusBezier bezier({1.0, 0.3});
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  double sink = 0.0;
  for (auto _ : state) {
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector2d w = slipfit::randomVector<2>(angle, rng);
      sink += bezier.evaluate(w(0), w(1)).position.x();
    }
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * 1000);
}

/// The peer: the closed-form point and normal from cos/sin.
void BM_TorusAnalyticEvaluate(benchmark::State& state) {
  const slipfit::TorusShape t{1.0, 0.3};
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
  double sink = 0.0;
  for (auto _ : state) {
    for (int i = 0; i < 1000; ++i) {
      const double a = angle(rng), b = angle(rng);
      sink += slipfit::torusPoint(t, a, b).x() + slipfit::torusNormal(a, b).y();
    }
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(state.iterations() * 1000);
}

void BM_TorusMesh(benchmark::State& state) {
  slipfit::TorusMeshParameters p;
  p.n_alpha = p.n_beta = static_cast<int>(state.range(0));
  for (auto _ : state) {
    const slipfit::SurfaceMesh mesh = slipfit::torusMesh({1.0, 0.3}, p);
    benchmark::DoNotOptimize(mesh.n_faces());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}

BENCHMARK(BM_TorusSampleArea)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TorusBezierEvaluate);
BENCHMARK(BM_TorusAnalyticEvaluate);
BENCHMARK(BM_TorusMesh)->Arg(100)->Arg(316)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
