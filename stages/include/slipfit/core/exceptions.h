#pragma once
/// \file Typed errors thrown by slipfit's stages. They derive from pcl::PCLException so that a PCL
/// application catches them exactly as it catches PCL's own.

#include <pcl/exceptions.h>

#include <string>

namespace slipfit {

/// Base of slipfit's errors; what() is the plain message (PCLException would prefix it with an
/// empty file/function location).
class Error : public pcl::PCLException {
 public:
  explicit Error(const std::string& what) : pcl::PCLException(what), message_(what) {}
  const char* what() const noexcept override { return message_.c_str(); }

 private:
  std::string message_;
};

/// A parameter is outside its documented range, or parameters contradict each other.
class InvalidParameterError : public Error {
 public:
  using Error::Error;
};

/// The input cannot give a meaningful answer (empty, too few points, no normals where needed, ...).
class DegenerateInputError : public Error {
 public:
  using Error::Error;
};

}  // namespace slipfit
