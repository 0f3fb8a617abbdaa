#include "slipfit/model_selection.h"

#include <cmath>
#include <limits>

namespace slipfit {

int parameterCount(PrimitiveType type) {
  switch (type) {
    case PrimitiveType::plane:
      return 3;
    case PrimitiveType::sphere:
      return 4;
    case PrimitiveType::cylinder:
      return 5;
    case PrimitiveType::cone:
      return 6;
    case PrimitiveType::torus:
      return 7;
  }
  return 7;
}

std::optional<std::size_t> selectSimplest(const std::vector<ModelCandidate>& candidates,
                                          double floor) {
  double best = std::numeric_limits<double>::infinity();
  for (const ModelCandidate& c : candidates)
    if (std::isfinite(c.rms))
      best = std::min(best, c.rms);
  if (!std::isfinite(best))
    return std::nullopt;
  const double limit = (1.0 + kAdequacyMargin) * best + std::max(0.0, floor);
  std::optional<std::size_t> chosen;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const ModelCandidate& c = candidates[i];
    if (!(std::isfinite(c.rms) && c.rms <= limit))
      continue;
    if (!chosen)
      chosen = i;
    else {
      const ModelCandidate& b = candidates[*chosen];
      const int pc = parameterCount(c.type), pb = parameterCount(b.type);
      if (pc < pb || (pc == pb && c.rms < b.rms))
        chosen = i;
    }
  }
  return chosen;
}

}  // namespace slipfit
