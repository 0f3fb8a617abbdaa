#include "slipfit/neighborhoods/precomputed_search.h"
#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

#include <pcl/point_types.h>

namespace slipfit {
namespace {

class PrecomputedSearchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cloud_ = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    for (int i = 0; i < 3; ++i)
      cloud_->push_back(pcl::PointXYZ(static_cast<float>(i), 0, 0));
    auto hoods = std::make_shared<Neighborhoods>();
    const pcl::Indices a{0, 1, 2}, b{1, 0, 2}, c{};
    const std::vector<float> da{0, 1, 4}, db{0, 1, 1};
    hoods->append(a.data(), da.data(), 3);
    hoods->append(b.data(), db.data(), 3);
    hoods->append(c.data(), nullptr, 0);
    search_ = std::make_shared<PrecomputedSearch<pcl::PointXYZ>>(hoods);
    search_->setInputCloud(cloud_);
  }
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud_;
  PrecomputedSearch<pcl::PointXYZ>::Ptr search_;
};

TEST_F(PrecomputedSearchTest, KnnReturnsStoredPrefix) {
  pcl::Indices ind;
  std::vector<float> d;
  EXPECT_EQ(search_->nearestKSearch(*cloud_, 0, 2, ind, d), 2);
  EXPECT_EQ(ind, (pcl::Indices{0, 1}));
  EXPECT_EQ(search_->nearestKSearch(1, 10, ind, d), 3);
  EXPECT_EQ(ind, (pcl::Indices{1, 0, 2}));
  EXPECT_EQ(search_->nearestKSearch(*cloud_, 2, 5, ind, d), 0);
}

TEST_F(PrecomputedSearchTest, RadiusFiltersByDistance) {
  pcl::Indices ind;
  std::vector<float> d;
  EXPECT_EQ(search_->radiusSearch(*cloud_, 0, 1.5, ind, d), 2);
  EXPECT_EQ(ind, (pcl::Indices{0, 1}));
  EXPECT_EQ(search_->radiusSearch(*cloud_, 0, 3.0, ind, d, 1), 1);
}

TEST_F(PrecomputedSearchTest, RefusesQueriesItCannotAnswer) {
  pcl::Indices ind;
  std::vector<float> d;
  EXPECT_THROW(search_->nearestKSearch(pcl::PointXYZ(0, 0, 0), 2, ind, d), InvalidParameterError);
  pcl::PointCloud<pcl::PointXYZ> other = *cloud_;
  EXPECT_THROW(search_->nearestKSearch(other, 0, 2, ind, d), InvalidParameterError);
  auto bigger = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>(*cloud_);
  bigger->push_back(pcl::PointXYZ(9, 9, 9));
  EXPECT_THROW(search_->setInputCloud(bigger), InvalidParameterError);
}

}  // namespace
}  // namespace slipfit
