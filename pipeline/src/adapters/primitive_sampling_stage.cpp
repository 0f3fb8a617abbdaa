#include "adapters.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/sampling/primitive_sampler.h"

#include <ostream>

namespace slipfit::pipeline::adapters {

namespace {

class PrimitiveSamplingStage : public Stage {
 public:
  void declare(OptionSet& o) override {
    o.bind(shape_);
    o.bind(p_);
  }

  void prepare() override {
    p_.primitive = shape_.primitive();
    p_.validate();
  }

  DataFlow flow() const override { return {0u, kPoints | kNormals}; }

  void run(PointData& data, RunContext& context) override {
    PrimitiveSamplingParameters p = p_;
    p.seed = context.seed;
    Eigen::Matrix3Xd x, n;
    std::vector<std::int32_t> outlier;
    samplePrimitive(p, x, n, &outlier);
    PointData out = sampledPointData(x, n);
    out.setField({"outlier", std::move(outlier)});
    data = std::move(out);
    context.report << "sampled " << primitiveTypeName(shape_.type) << ": " << data.size()
                   << " points\n";
  }

 private:
  PrimitiveDescription shape_;
  PrimitiveSamplingParameters p_;
};

}  // namespace

StageInfo primitiveSamplingInfo() {
  return {"primitive_sampling",
          "seeded points with normals on a plane, sphere, cylinder or cone with known parameters "
          "(noise, outliers, partial coverage, normal noise and sign flips)",
          [] { return std::unique_ptr<Stage>(new PrimitiveSamplingStage); }};
}

}  // namespace slipfit::pipeline::adapters
