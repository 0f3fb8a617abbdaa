#include "slipfit/sampling/labelled_scene.h"

#include "slipfit/core/exceptions.h"

#include <utility>

namespace slipfit {

void LabelledSceneParameters::validate() const {
  validateDeclared(*this, "scene sampling");
  if (layout == SceneLayout::fixed)
    fixedLayout().validate();
  else if (layout == SceneLayout::random)
    randomLayout().validate();
  else
    kinematicLayout().validate();
  if (layout == SceneLayout::kinematic && outlier_fraction > 0.0)
    throw InvalidParameterError("scene sampling: the kinematic layout has no outliers");
}

LabelledScene sampleLabelledScene(const LabelledSceneParameters& parameters) {
  parameters.validate();
  LabelledScene scene;
  if (parameters.layout == SceneLayout::fixed) {
    sampleScene(parameters.fixedLayout(), scene.points, scene.normals, scene.labels);
    for (const auto& s : scenePrimitives())
      scene.truth.push_back(s.primitive);
  } else if (parameters.layout == SceneLayout::random) {
    std::vector<Primitive> truth;
    sampleRandomScene(parameters.randomLayout(), scene.points, scene.normals, scene.labels, truth);
    scene.truth.assign(truth.begin(), truth.end());
  } else {
    KinematicScene k = sampleKinematicScene(parameters.kinematicLayout());
    scene.points = std::move(k.points);
    scene.normals = std::move(k.normals);
    scene.labels = std::move(k.labels);
    scene.truth = std::move(k.truth);
  }
  scene.types.assign(scene.labels.size(), -1);
  for (std::size_t i = 0; i < scene.labels.size(); ++i)
    if (scene.labels[i] >= 0)
      scene.types[i] = truthTypeCode(scene.truth[static_cast<std::size_t>(scene.labels[i])]);
  return scene;
}

}  // namespace slipfit
