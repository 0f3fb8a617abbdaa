// Closed-form weighted estimators from 10^3 to 10^7 points (points per second), with a memory-read
// bandwidth baseline in the same binary: the sum of a double array of the same size as the
// points (3N doubles, what every estimator must read at least once).
//
//   build/bench/bench_fitting --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "slipfit/fitting/weighted_fit.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <benchmark/benchmark.h>

#include <map>
#include <numeric>

namespace {

struct Data {
  Eigen::Matrix3Xd points, normals;
  Eigen::VectorXd weights;
};

const Data& data(slipfit::PrimitiveType type, std::int64_t n) {
  static std::map<std::pair<int, std::int64_t>, Data> cache;
  auto& d = cache[{static_cast<int>(type), n}];
  if (d.points.cols() == n)
    return d;
  slipfit::PrimitiveSamplingParameters p;
  switch (type) {
    case slipfit::PrimitiveType::plane:
      p.primitive = slipfit::Plane{Eigen::Vector3d(0, 0.6, 0.8), 1.0};
      break;
    case slipfit::PrimitiveType::sphere:
      p.primitive = slipfit::Sphere{Eigen::Vector3d(1, 2, 3), 1.0};
      break;
    case slipfit::PrimitiveType::cylinder:
      p.primitive = slipfit::Cylinder{Eigen::Vector3d(0, 0.6, 0.8), Eigen::Vector3d(1, 0, 0), 0.5};
      break;
    case slipfit::PrimitiveType::cone:
      p.primitive = slipfit::Cone{Eigen::Vector3d(0, 0.6, 0.8), Eigen::Vector3d(1, 0, 0), 0.5};
      break;
  }
  p.points = static_cast<std::size_t>(n);
  p.noise = 0.01;
  p.extent_min = 0.2;
  slipfit::samplePrimitive(p, d.points, d.normals);
  d.weights = Eigen::VectorXd::Ones(n);
  return d;
}

void BM_Estimator(benchmark::State& state) {
  const auto type = static_cast<slipfit::PrimitiveType>(state.range(0));
  const Data& d = data(type, state.range(1));
  slipfit::FitOptions options;
  options.refine = false;
  for (auto _ : state) {
    slipfit::FitResult r;
    switch (type) {
      case slipfit::PrimitiveType::plane:
        r = slipfit::estimatePlane(d.points, d.weights, options);
        break;
      case slipfit::PrimitiveType::sphere:
        r = slipfit::estimateSphere(d.points, d.weights, options);
        break;
      case slipfit::PrimitiveType::cylinder:
        r = slipfit::estimateCylinder(d.points, d.normals, d.weights, options);
        break;
      case slipfit::PrimitiveType::cone:
        r = slipfit::estimateCone(d.points, d.normals, d.weights, options);
        break;
    }
    benchmark::DoNotOptimize(r.loss_algebraic);
  }
  state.SetItemsProcessed(state.iterations() * state.range(1));
  state.SetLabel(std::string(slipfit::primitiveTypeName(type)));
}

void BM_ReadBandwidth(benchmark::State& state) {
  const Data& d = data(slipfit::PrimitiveType::plane, state.range(1));
  const double* p = d.points.data();
  const auto n = 3 * d.points.cols();
  for (auto _ : state) {
    double s = 0.0;
    for (Eigen::Index i = 0; i < n; ++i)
      s += p[i];
    benchmark::DoNotOptimize(s);
  }
  state.SetItemsProcessed(state.iterations() * state.range(1));
  state.SetLabel("sum of 3N doubles");
}

void Args(benchmark::internal::Benchmark* b) {
  for (int type = 0; type < 4; ++type)
    for (std::int64_t n : {1000, 10000, 100000, 1000000, 10000000})
      b->Args({type, n});
}
void BandwidthArgs(benchmark::internal::Benchmark* b) {
  for (std::int64_t n : {1000, 10000, 100000, 1000000, 10000000})
    b->Args({0, n});
}

BENCHMARK(BM_ReadBandwidth)->Apply(BandwidthArgs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Estimator)->Apply(Args)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
