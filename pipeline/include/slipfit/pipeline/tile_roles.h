#pragma once
/// \file How a stage takes part in a tiled run (docs/TILING.md), said in C++: the tile runner asks
/// a configured stage for these interfaces (dynamic_cast) and sets typed values through them,
/// never by the stage's type name, `--set` strings or its options' text.

#include "slipfit/filters/subsampling.h"
#include "slipfit/render/splat_renderer.h"

#include <optional>
#include <string>

namespace slipfit::pipeline {

/// A picture of segments: its file name and camera.
struct RenderRequest {
  std::string name;  ///< file name of the PNG inside output.dir
  RenderParameters camera;
};

/// A stage whose results a tiled run joins across tiles; a tiled pipeline ends with one
/// (segmentation). Each tile runs it as configured, without its picture; the merge writes the
/// joined files under the names it gives and draws the picture of the whole.
class JoinedAcrossTiles {
 public:
  virtual ~JoinedAcrossTiles() = default;
  /// The files it writes into output.dir, by role.
  struct Files {
    std::string report;    ///< primitives.yaml: one entry per segment
    std::string segments;  ///< segments.ply: every point with its label
    std::string las;       ///< segments.las, the same points as LAS; empty when not asked for
  };
  virtual Files joinedFiles() const = 0;
  /// Its picture as configured; nullopt when it draws none.
  virtual std::optional<RenderRequest> picture() const = 0;
  /// Leaves out what the merge writes for the whole cloud from its joined files (the picture,
  /// segments.las): a tile's are not the run's. \a share: the tile's points over the whole
  /// cloud's, for what it samples of the whole cloud's (the noise estimate's neighborhoods).
  virtual void forTile(double share) = 0;
  /// The option of an output it is asked for that a tiled run does not join (a tiled run refuses
  /// the config); empty when there is none.
  virtual std::string unjoinedOutput() const = 0;
  /// The option set to a value a tiled run cannot join ("surfaces: kinematic"), or empty.
  virtual std::string unjoinedSetting() const { return ""; }
};

/// A stage that analyses a sample of the cloud chosen for the whole cloud (subsample): a tiled
/// run gives every tile the sampling the untiled run would use.
class SampledAnalysis {
 public:
  virtual ~SampledAnalysis() = default;
  /// The sampling as configured.
  virtual const SubsampleParameters& sampling() const = 0;
  /// Replaces it (validated: InvalidParameterError).
  virtual void setSampling(const SubsampleParameters& sampling) = 0;
};

}  // namespace slipfit::pipeline
