#pragma once
/// \file The one declaration of a library parameter: its name, help, unit and range. A
/// parameters struct lists each of its fields once, with its declaration, in a static
/// `forEachParameter(self, visit)`; its validate() checks the fields against those declarations
/// (validateDeclared), and the pipeline binds its options to the same list — their parsing,
/// `slipfit describe` and docs/stages.md read it too (pipeline/options.h, OptionSet::bind). In
/// the spirit of PDAL's ProgramArgs and libpointmatcher's parameter tables.
///
/// A declaration's unit is the user's (degrees for angles); `scale` converts it to the field's
/// (a field in radians declared in degrees has scale kDegree): field = user value × scale.

#include "slipfit/core/exceptions.h"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

namespace slipfit {

/// Bounds on a parameter, in the user's unit; each side unset (unbounded), closed or open.
struct ParameterRange {
  std::optional<double> low, high;
  bool low_open = false, high_open = false;

  bool contains(double value) const {
    const bool below = low && (low_open ? !(value > *low) : !(value >= *low));
    const bool beyond = high && (high_open ? !(value < *high) : !(value <= *high));
    return !below && !beyond;
  }
  bool bounded() const { return low || high; }
  ParameterRange& setLow(double value, bool open) {
    low = value;
    low_open = open;
    return *this;
  }
  ParameterRange& setHigh(double value, bool open) {
    high = value;
    high_open = open;
    return *this;
  }
  /// "[3, 10000]", "(0, inf)", "" when unbounded; numbers to 9 significant digits.
  std::string text() const;
};

/// "0.5", "1e+09", "inf": a number as ranges and defaults print it (9 significant digits).
std::string parameterNumberText(double value);

struct ParameterDeclaration {
  std::string_view name;
  std::string_view help;
  std::string_view unit;  ///< the user's unit ("deg", "units", "points"), "" for none
  double scale = 1.0;     ///< field value = user value × scale
  ParameterRange range;
  bool required = false;  ///< the user must give it (the default is only a placeholder)

  /// Builders, chained: parameter("k", "Neighbors per point.").in("neighbors").between(3, 10000).
  ParameterDeclaration& in(std::string_view user_unit, double to_field = 1.0) {
    unit = user_unit;
    scale = to_field;
    return *this;
  }
  ParameterDeclaration& between(double lo, double hi) { return atLeast(lo).atMost(hi); }
  ParameterDeclaration& above(double lo) {
    range.setLow(lo, true);
    return *this;
  }
  ParameterDeclaration& atLeast(double lo) {
    range.setLow(lo, false);
    return *this;
  }
  ParameterDeclaration& below(double hi) {
    range.setHigh(hi, true);
    return *this;
  }
  ParameterDeclaration& atMost(double hi) {
    range.setHigh(hi, false);
    return *this;
  }
  ParameterDeclaration& mustBeGiven() {
    required = true;
    return *this;
  }
};

inline ParameterDeclaration parameter(std::string_view name, std::string_view help) {
  ParameterDeclaration d;
  d.name = name;
  d.help = help;
  return d;
}

/// Throws InvalidParameterError "<context>: <name> must be in <range> <unit>, got <value>" when
/// \a field_value (in the field's unit) lies outside the declared range or is not finite.
void checkDeclared(std::string_view context, const ParameterDeclaration& declaration,
                   double field_value);

namespace detail {

template <typename T>
struct IsOptional : std::false_type {};
template <typename T>
struct IsOptional<std::optional<T>> : std::true_type {};

template <typename T>
void checkField(std::string_view context, const ParameterDeclaration& d, const T& field) {
  if constexpr (IsOptional<T>::value) {
    if (field)
      checkField(context, d, *field);
  } else if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    if (d.range.bounded())
      checkDeclared(context, d, static_cast<double>(field));
  }
  // Enumerations, flags and vectors have no range to check.
}

}  // namespace detail

/// Checks every declared field of \a parameters against its range (see checkDeclared).
template <typename Parameters>
void validateDeclared(const Parameters& parameters, std::string_view context) {
  Parameters::forEachParameter(parameters,
                               [&](const auto& field, const ParameterDeclaration& d, auto&&...) {
                                 detail::checkField(context, d, field);
                               });
}

}  // namespace slipfit
