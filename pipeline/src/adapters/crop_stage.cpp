#include "adapters.h"
#include "point_filter.h"

#include "slipfit/point_filters.h"

namespace slipfit::pipeline::adapters {

namespace {

/// PCL's PassThrough on one coordinate and/or CropBox on an axis-aligned box.
class CropStage : public Stage {
 public:
  void declare(OptionSet& o) override { o.bind(p_); }
  void prepare() override { p_.validate(); }
  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    // The limits are in the input's frame; the points are at its coordinates − frame.shift.
    keepFiltered(data, crop(data.cloud, p_, data.frame.shift), context, "crop");
  }

 private:
  CropParameters p_;
};

}  // namespace

StageInfo cropInfo() {
  return {"crop",
          "keeps the points with one coordinate in [min, max] (PCL's PassThrough) and/or inside "
          "an axis-aligned box (PCL's CropBox), or outside them with negative; the others are "
          "absent from every output",
          [] { return std::unique_ptr<Stage>(new CropStage); }};
}

}  // namespace slipfit::pipeline::adapters
