#pragma once
/// \file The segmentation kernel, apart from its PCL front end (SlippageSegmentation,
/// segmentation.h): the phases of SegmentationPhase run in order over one SegmentationState.
/// segmentBySlippage runs them all, then finalize(). Each phase can be run and inspected on its
/// own (regions(), fits(), progress()), which is how the tests look inside. The design:
/// docs/THEORY.md §6, whose phase numbers are SegmentationPhase's.

#include "slipfit/segmentation/segmentation.h"
#include "slipfit/segmentation/segmentation_phase.h"
#include "slipfit/segmentation/segmentation_state.h"

#include <Eigen/Core>

#include <functional>
#include <initializer_list>
#include <string_view>
#include <vector>

namespace slipfit {

class SegmentationKernel {
 public:
  using Phase = SegmentationPhase;

  /// Checks the inputs (sizes, finite normals, parameters); throws DegenerateInputError or
  /// InvalidParameterError. The arrays must outlive the kernel.
  SegmentationKernel(const Eigen::Ref<const Eigen::Matrix3Xd>& points,
                     const Eigen::Ref<const Eigen::Matrix3Xd>& normals,
                     const Neighborhoods& neighborhoods,
                     const std::vector<SlippageType>& local_types,
                     const SegmentationParameters& parameters);

  /// Called with each phase's name as it starts (a progress display); none by default.
  void setPhaseListener(std::function<void(std::string_view)> listener) {
    on_phase_ = std::move(listener);
  }

  /// Runs one phase; its wall time goes to progress().timings.
  void run(Phase phase);
  /// Runs the phases from \a first to \a last in their order, except those in \a skip.
  void runPhases(Phase first, Phase last, std::initializer_list<Phase> skip = {});
  /// Ends the run: the result with its segments largest first, each refitted on all its members
  /// (its time last in timings, as "finalize").
  SegmentationResult finalize();

  /// The regions so far (empty member lists are regions dropped or merged away).
  const std::vector<std::vector<int>>& regions() const { return state_.regions; }
  /// Each region's fit so far (that of a region dropped or merged away is stale).
  const std::vector<FitResult>& fits() const { return state_.fits; }
  /// The tolerances and counters so far (segments are filled by finalize()).
  const SegmentationResult& progress() const { return state_.result; }

 private:
  /// Runs one phase (no timing).
  void runPhase(Phase phase);

  SegmentationState state_;
  std::function<void(std::string_view)> on_phase_;
};

}  // namespace slipfit
