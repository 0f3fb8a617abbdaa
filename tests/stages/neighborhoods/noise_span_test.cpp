// Neighborhoods that span a sensor's noise (NeighborhoodParameters::span_noise): where the noise
// across a surface is wider than the k nearest reach, the k nearest lie in a slab of the noise and
// their plane is not the surface's; the widened lists are. Thin walls, creases and clean surfaces
// keep their k nearest. SurfaceThickness, the measure behind it, is tested first.
#include "slipfit/neighborhoods/neighborhood_selection.h"
#include "slipfit/neighborhoods/surface_thickness.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

namespace slipfit {
namespace {

using XyzCloud = pcl::PointCloud<pcl::PointXYZ>;

pcl::Indices all(const XyzCloud& c) {
  pcl::Indices idx(c.size());
  std::iota(idx.begin(), idx.end(), 0);
  return idx;
}

/// A side × side grid of spacing 1 in x–y, jittered by a tenth of a spacing (no lattice), with
/// height z = height(x, y) plus Gaussian noise \a sigma along z.
template <typename Height>
XyzCloud::Ptr sheet(int side, double sigma, std::uint64_t seed, Height height) {
  auto c = std::make_shared<XyzCloud>();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const double x = i + jitter(rng), y = j + jitter(rng);
      c->push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y),
                                 static_cast<float>(height(x, y) + sigma * noise(rng))));
    }
  return c;
}

TEST(SurfaceThickness, MeasuresNoiseOffACurvedSurfaceAndTellsTwoSheetsApart) {
  // A noise-free saddle, 0.6 deep at its rim: the quadric height field over the points' principal
  // plane explains it (that plane is tilted off x–y by the jitter: what is left is a small
  // fraction of the depth), where a plane would leave 0.15.
  const auto bowl = sheet(20, 0.0, 1, [](double x, double y) {
    return 0.02 * (x - 9.5) * (x - 9.5) - 0.01 * (y - 9.5) * (y - 9.5);
  });
  EXPECT_LT(surfaceThickness(*bowl, all(*bowl)).rms, 0.01);
  // Gaussian noise σ = 0.05 on the same bowl, 400 points: σ̂ has a relative standard error of
  // 1/√(2ν) = 3.6 % (ν = 394), the sample kurtosis one of √(24/n) = 0.245; three of each.
  const auto noisy = sheet(20, 0.05, 2, [](double x, double y) {
    return 0.02 * (x - 10) * (x - 10) - 0.01 * (y - 10) * (y - 10);
  });
  const SurfaceThickness t = surfaceThickness(*noisy, all(*noisy));
  EXPECT_NEAR(t.rms, 0.05, 3 * 0.036 * 0.05);
  EXPECT_NEAR(t.kurtosis, 3.0, 3 * 0.245);
  // Two flat sheets 0.4 apart, 200 points each: residuals ±0.2, kurtosis 1.
  auto wall = sheet(20, 0.0, 3, [](double, double) { return 0.0; });
  const auto other = sheet(20, 0.0, 4, [](double, double) { return 0.4; });
  *wall += *other;
  const SurfaceThickness w = surfaceThickness(*wall, all(*wall));
  EXPECT_NEAR(w.rms, 0.2, 0.01);
  EXPECT_NEAR(w.kurtosis, 1.0, 0.05);
}

/// The angle between each point's least-variance direction over its list and +z, degrees.
std::vector<double> normalErrors(const XyzCloud& c, const Neighborhoods& hoods) {
  std::vector<double> out;
  for (std::size_t i = 0; i < c.size(); ++i) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto j : hoods[i])
      mean += c[j].getVector3fMap().cast<double>();
    mean /= static_cast<double>(hoods[i].size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const auto j : hoods[i]) {
      const Eigen::Vector3d d = c[j].getVector3fMap().cast<double>() - mean;
      cov += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    out.push_back(std::acos(std::min(1.0, std::abs(eig.eigenvectors().col(0).z()))) * 180.0 / M_PI);
  }
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

struct Selected {
  Neighborhoods hoods;
  NeighborhoodStatistics stats;
};

Selected select(const XyzCloud::Ptr& cloud, bool span_noise, int threads = 0) {
  NeighborhoodParameters p;
  p.k = 12;
  p.span_noise = span_noise;
  p.threads = threads;
  NeighborhoodSelection<pcl::PointXYZ> s;
  s.setParameters(p);
  s.setInputCloud(cloud);
  Selected out;
  s.compute(out.hoods);
  out.stats = s.statistics();
  return out;
}

TEST(NoiseSpan, ListsSpanANoiseWiderThanTheKNearest) {
  // A plane seen face-on with noise σ = 3 spacings along the view (a depth camera's far wall):
  // the 12 nearest lie within about one σ, a ball in the slab, whose least-variance direction
  // is anywhere (median 45°). Widened to 4 σ (8 k points of a disc of radius 12, lateral spread
  // 6 per axis), the normal's error is σ / (√96 · 6) = 3.1° per axis, a median of 1.18 × that =
  // 3.7° in all; the ball cuts the slab at its rim and the k nearest are kept whole: at most twice
  // that.
  const double sigma = 3.0;
  const auto wall = sheet(100, sigma, 5, [](double, double) { return 0.0; });
  const Selected off = select(wall, false);
  const Selected on = select(wall, true);
  EXPECT_EQ(off.stats.noise_widened, 0u);
  EXPECT_GE(on.stats.noise_widened, wall->size() * 9 / 10);
  // σ is measured at the samples as the thickness of a ball of 5 σ: within a fifth of the truth.
  EXPECT_GT(on.stats.noise_sigma_low, 0.8 * sigma);
  EXPECT_LT(on.stats.noise_sigma_high, 1.2 * sigma);
  const double before = median(normalErrors(*wall, off.hoods));
  const double after = median(normalErrors(*wall, on.hoods));
  EXPECT_GT(before, 20.0);
  EXPECT_LT(after, 7.5);
  std::cout << "normal error, median: k nearest " << before << "°, spanning the noise " << after
            << "°; σ " << on.stats.noise_sigma_low << ".." << on.stats.noise_sigma_high << "\n";
  // The same lists with one thread and with two.
  const Selected one = select(wall, true, 1);
  ASSERT_EQ(one.hoods.size(), on.hoods.size());
  for (std::size_t i = 0; i < wall->size(); ++i)
    ASSERT_TRUE(std::equal(one.hoods[i].begin(), one.hoods[i].end(), on.hoods[i].begin(),
                           on.hoods[i].end()))
        << i;
}

TEST(NoiseSpan, CleanSurfacesCreasesAndThinWallsKeepTheirKNearest) {
  // A faint noise (a tenth of a spacing), a right-angled crease, and a noise-free thin wall whose
  // two sheets one spacing apart both lie in the k nearest (its thickness, half the gap, settles
  // like a noise's but stays below half the k-th nearest distance). The wall that does get past
  // that — Fit4CAD's PC13, a plate one unit thick, sampled unevenly — is held by the kurtosis
  // rule, and the benchmark.fit4cad gate fails without it (PC13's Dice 0.477 → 0.254).
  const auto faint = sheet(60, 0.1, 6, [](double, double) { return 0.0; });
  const auto crease = sheet(60, 0.0, 7, [](double x, double) { return std::abs(x - 30.0); });
  auto wall = sheet(60, 0.0, 8, [](double, double) { return 0.0; });
  *wall += *sheet(60, 0.0, 9, [](double, double) { return 1.0; });
  for (const auto& cloud : {faint, crease, wall}) {
    const Selected s = select(cloud, true);
    EXPECT_EQ(s.stats.noise_widened, 0u);
    EXPECT_EQ(s.stats.max_size, 12u);
  }
}

}  // namespace
}  // namespace slipfit
