#pragma once
/// \file π and the degree in radians: one definition for the library and the pipeline.

namespace slipfit {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;  ///< one degree, in radians

}  // namespace slipfit
