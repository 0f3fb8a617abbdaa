#pragma once
/// \file The check every parameters struct's validate() gets: the defaults pass, and one field set
/// out of its range throws InvalidParameterError whose message names that field.

#include "slipfit/core/exceptions.h"

#include <gtest/gtest.h>

#include <string>

namespace slipfit::testing {

/// Options{} with \a spoil applied must be refused, naming \a field.
template <typename Options, typename Spoil>
void expectRefused(const std::string& field, Spoil spoil) {
  EXPECT_NO_THROW(Options{}.validate());
  Options options;
  spoil(options);
  try {
    options.validate();
    ADD_FAILURE() << field << " was accepted";
  } catch (const InvalidParameterError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

}  // namespace slipfit::testing
