#include "slipfit/sampling/labelled_scene.h"

namespace slipfit {

void LabelledSceneParameters::validate() const {
  validateDeclared(*this, "scene sampling");
  if (layout == SceneLayout::fixed)
    fixedLayout().validate();
  else
    randomLayout().validate();
}

LabelledScene sampleLabelledScene(const LabelledSceneParameters& parameters) {
  parameters.validate();
  LabelledScene scene;
  if (parameters.layout == SceneLayout::fixed) {
    sampleScene(parameters.fixedLayout(), scene.points, scene.normals, scene.labels);
    for (const auto& s : scenePrimitives())
      scene.truth.push_back(s.primitive);
  } else {
    sampleRandomScene(parameters.randomLayout(), scene.points, scene.normals, scene.labels,
                      scene.truth);
  }
  scene.types.assign(scene.labels.size(), -1);
  for (std::size_t i = 0; i < scene.labels.size(); ++i)
    if (scene.labels[i] >= 0)
      scene.types[i] =
          static_cast<std::int32_t>(scene.truth[static_cast<std::size_t>(scene.labels[i])].index());
  return scene;
}

}  // namespace slipfit
