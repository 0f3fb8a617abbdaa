#pragma once
/// \file Typed errors thrown by slipfit's stages. They derive from pcl::PCLException so that a PCL
/// application catches them exactly as it catches PCL's own.

#include <pcl/exceptions.h>

#include <string>

namespace slipfit {

/// A parameter is outside its documented range, or parameters contradict each other.
class InvalidParameterError : public pcl::PCLException {
 public:
  explicit InvalidParameterError(const std::string& what) : pcl::PCLException(what) {}
};

/// The input cannot give a meaningful answer (empty, too few points, no normals where needed, ...).
class DegenerateInputError : public pcl::PCLException {
 public:
  explicit DegenerateInputError(const std::string& what) : pcl::PCLException(what) {}
};

}  // namespace slipfit
