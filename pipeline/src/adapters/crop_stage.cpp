#include "adapters.h"
#include "point_filter.h"

#include "slipfit/pipeline/errors.h"

#include <pcl/filters/crop_box.h>
#include <pcl/filters/passthrough.h>

#include <array>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

namespace slipfit::pipeline::adapters {

namespace {

enum class Axis { none, x, y, z };
constexpr std::array<std::pair<Axis, std::string_view>, 4> kAxisNames{{
    {Axis::none, "none"},
    {Axis::x, "x"},
    {Axis::y, "y"},
    {Axis::z, "z"},
}};

/// PCL's PassThrough on one coordinate and/or CropBox on an axis-aligned box.
class CropStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.add("field", field_, kAxisNames,
          "PassThrough: the coordinate limited to [min, max] (PCL's cylinder tutorial keeps z in "
          "[0, 1.5] of a Kinect scan).");
    o.add("min", min_, "PassThrough: the smallest value kept (inclusive).").unit("cloud units");
    o.add("max", max_, "PassThrough: the largest value kept (inclusive).").unit("cloud units");
    o.add("box_min", box_min_, "CropBox: the box's lowest corner [x, y, z].").unit("cloud units");
    o.add("box_max", box_max_, "CropBox: the box's highest corner [x, y, z].").unit("cloud units");
    o.add("negative", negative_,
          "Keep the points outside the limits instead (every limit given is applied).");
  }

  void prepare() override {
    const bool pass = field_ != Axis::none;
    if (pass != (min_ || max_))
      throw OptionValueError(pass ? "field needs min and/or max"
                                  : "min and max need field (x, y or z)");
    if (min_ && max_ && !(*min_ <= *max_))
      throw OptionValueError("min must not exceed max");
    if (box_min_.has_value() != box_max_.has_value())
      throw OptionValueError("box_min and box_max go together");
    if (box_min_ && !(box_min_->array() < box_max_->array()).all())
      throw OptionValueError("box_min must be below box_max on every axis");
    if (!pass && !box_min_)
      throw OptionValueError("give field with min/max, or box_min and box_max");
  }

  DataFlow flow() const override { return {kPoints, 0u}; }

  void run(PointData& data, RunContext& context) override {
    requireInputCloud(data);
    pcl::Indices kept;
    std::ostringstream why;
    if (field_ != Axis::none) {
      pcl::PassThrough<pcl::PointNormal> pass;
      pass.setInputCloud(data.cloud);
      const std::string name(kAxisNames[static_cast<std::size_t>(field_)].second);
      pass.setFilterFieldName(name);
      const double lo = min_.value_or(-std::numeric_limits<float>::max());
      const double hi = max_.value_or(std::numeric_limits<float>::max());
      // The limits are in the input's frame; the points are at its coordinates − frame.shift.
      const double t = data.frame.shift[static_cast<int>(field_) - 1];
      pass.setFilterLimits(static_cast<float>(lo - t), static_cast<float>(hi - t));
      pass.setNegative(negative_ && !box_min_);
      pass.filter(kept);
      why << name << " in [" << lo << ", " << hi << "]";
    }
    if (box_min_) {
      pcl::CropBox<pcl::PointNormal> box;
      box.setInputCloud(data.cloud);
      if (field_ != Axis::none)
        box.setIndices(pcl::make_shared<pcl::Indices>(kept));
      const Eigen::Vector3f low = (box_min_->cast<double>() - data.frame.shift).cast<float>();
      const Eigen::Vector3f high = (box_max_->cast<double>() - data.frame.shift).cast<float>();
      box.setMin(Eigen::Vector4f(low.x(), low.y(), low.z(), 1.0f));
      box.setMax(Eigen::Vector4f(high.x(), high.y(), high.z(), 1.0f));
      box.setNegative(negative_ && field_ == Axis::none);
      box.filter(kept);
      why << (field_ != Axis::none ? ", " : "") << "inside the box [" << box_min_->transpose()
          << "] – [" << box_max_->transpose() << "]";
    }
    if (negative_ && field_ != Axis::none && box_min_)
      kept = complement(kept, data.size());
    keepFiltered(data, kept, context, "crop", (negative_ ? "kept outside: " : "kept ") + why.str());
  }

 private:
  static pcl::Indices complement(const pcl::Indices& in, std::size_t n) {
    std::vector<char> inside(n, 0);
    for (const auto i : in)
      inside[static_cast<std::size_t>(i)] = 1;
    pcl::Indices out;
    for (std::size_t i = 0; i < n; ++i)
      if (!inside[i])
        out.push_back(static_cast<pcl::index_t>(i));
    return out;
  }

  Axis field_ = Axis::none;
  std::optional<double> min_, max_;
  std::optional<Eigen::Vector3f> box_min_, box_max_;
  bool negative_ = false;
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
