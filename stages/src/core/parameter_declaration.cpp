#include "slipfit/core/parameter_declaration.h"

#include <cmath>
#include <sstream>

namespace slipfit {

std::string parameterNumberText(double value) {
  if (std::isinf(value))
    return value > 0 ? "inf" : "-inf";
  std::ostringstream os;
  os.imbue(std::locale::classic());
  os.precision(9);
  os << value;
  return os.str();
}

std::string ParameterRange::text() const {
  if (!low && !high)
    return "";
  return std::string(low_open ? "(" : "[") + (low ? parameterNumberText(*low) : "-inf") + ", " +
         (high ? parameterNumberText(*high) + (high_open ? ")" : "]") : "inf)");
}

void checkDeclared(std::string_view context, const ParameterDeclaration& declaration,
                   double field_value) {
  const double value = field_value / declaration.scale;
  // The bounds apply to the field's own value (a bound in degrees times its scale in radians): a
  // field set from the user's bound converts exactly as the bound does.
  ParameterRange in_field = declaration.range;
  if (in_field.low)
    *in_field.low *= declaration.scale;
  if (in_field.high)
    *in_field.high *= declaration.scale;
  if (std::isfinite(field_value) && in_field.contains(field_value))
    return;
  const std::string unit = declaration.unit.empty() ? "" : " " + std::string(declaration.unit);
  throw InvalidParameterError(std::string(context) + ": " + std::string(declaration.name) +
                              " must be in " + declaration.range.text() + unit + ", got " +
                              parameterNumberText(value) + unit);
}

}  // namespace slipfit
