// PointData's subset and carry-back operations, which the subsample stage and large clouds rely
// on: keepOnly must not touch a shared cloud and must release what it removes; expandToFull
// copies each representative's results to every point, or drops the stage fields on request.
#include "slipfit/pipeline/point_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace slipfit::pipeline {
namespace {

PointData line(std::size_t n) {
  PointData d;
  for (std::size_t i = 0; i < n; ++i) {
    pcl::PointNormal p;
    p.x = static_cast<float>(i);
    p.y = p.z = 0.0f;
    p.normal_x = p.normal_y = p.normal_z = std::numeric_limits<float>::quiet_NaN();
    d.cloud->push_back(p);
  }
  std::vector<std::int32_t> id(n);
  for (std::size_t i = 0; i < n; ++i)
    id[i] = static_cast<std::int32_t>(i);
  d.setField({"id", id});
  return d;
}

TEST(PointData, KeepOnlyLeavesASharedCloudAloneAndReleasesTheRest) {
  PointData d = line(10000);
  const auto shared = d.cloud;
  std::vector<char> keep(10000, 0);
  for (std::size_t i = 0; i < 10000; i += 100)
    keep[i] = 1;
  d.keepOnly(keep);
  ASSERT_EQ(d.size(), 100u);
  EXPECT_EQ(shared->size(), 10000u);  // the other holder still sees every point
  EXPECT_EQ((*shared)[5].x, 5.0f);
  EXPECT_EQ((*d.cloud)[7].x, 700.0f);
  EXPECT_LE(d.cloud->points.capacity(), 100u);
  const auto& id = std::get<std::vector<std::int32_t>>(d.field("id")->values);
  ASSERT_EQ(id.size(), 100u);
  EXPECT_EQ(id[7], 700);
  EXPECT_LE(id.capacity(), 100u);
}

TEST(PointData, ExpandToFullCopiesRepresentativesOrDropsStageFields) {
  for (const bool fields : {true, false}) {
    PointData analysis = line(3);
    analysis.full = std::make_shared<PointData>(line(6));
    analysis.full->fields.clear();
    analysis.representative = {0, 0, 1, 1, 2, -1};  // the last point was not finite
    analysis.has_normals = true;
    for (std::size_t i = 0; i < 3; ++i)
      (*analysis.cloud)[i].getNormalVector3fMap() = Eigen::Vector3f(0, 0, 1 + i);
    analysis.expandToFull(fields);
    ASSERT_EQ(analysis.size(), 6u);
    EXPECT_FALSE(analysis.full);
    EXPECT_EQ((*analysis.cloud)[3].x, 3.0f);         // its own coordinates
    EXPECT_EQ((*analysis.cloud)[3].normal_z, 2.0f);  // its representative's normal
    EXPECT_TRUE(std::isnan((*analysis.cloud)[5].normal_z));
    if (fields) {
      const auto& id = std::get<std::vector<std::int32_t>>(analysis.field("id")->values);
      EXPECT_EQ(id, (std::vector<std::int32_t>{0, 0, 1, 1, 2, 0}));
    } else {
      EXPECT_EQ(analysis.field("id"), nullptr);
    }
  }
}

}  // namespace
}  // namespace slipfit::pipeline
