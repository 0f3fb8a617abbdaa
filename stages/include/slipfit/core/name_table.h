#pragma once
/// \file The tables of enumerators and their names (kPrimitiveTypeNames, kSlippageTypeNames, ...)
/// read one way: one lookup for every table.

#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

namespace slipfit {

/// The name of \a value in \a table, or "?" for a value the table does not hold.
template <typename Enum, std::size_t N>
constexpr std::string_view nameIn(const std::array<std::pair<Enum, std::string_view>, N>& table,
                                  Enum value) {
  for (const auto& [v, name] : table)
    if (v == value)
      return name;
  return "?";
}

}  // namespace slipfit
