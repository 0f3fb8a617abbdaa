#pragma once
/// \file Checks of a file's data against its header, before PCL's readers see it. PCL 1.13's
/// readers guess where the data disagree with the header: a PCD ascii row of 2 or 4 values where
/// 3 are declared becomes (0, 0, 0); an ascii PLY uchar 300 is read as 44; rows past the count
/// the header announces are dropped without a word. Each is refused here in one line that names
/// the file and the line of the data. The rules:
/// - ascii: every row has exactly the values its header declares (a PLY list: its count, then
///   that many items); an integer value is a whole number its type holds; a floating-point value
///   is not checked here (text that is no number reads as NaN, which input.nan then handles);
///   PLY rows are lines and no blank line may stand between them; PCD skips blank lines as PCL
///   does; nothing but blank lines follows the last row;
/// - binary: no byte follows the data of the last element (PLY) or the announced points (PCD).
/// The file is read line by line: memory does not grow with it.

#include <cstdint>
#include <string>
#include <vector>

namespace slipfit::pipeline::detail {

/// Checks the data of the PLY at \a path (its header already checked) against the header.
void checkPlyData(const std::string& path, const std::string& where);

/// One PCD field as its header declares it.
struct PcdField {
  std::string name;
  char type = 'F';  ///< F, I or U
  std::uint64_t size = 4, count = 1;
};

/// Checks the data of the PCD at \a path from byte \a data_at on: \a points rows of \a fields,
/// stored as \a storage ("ascii" or "binary"; binary_compressed is checked elsewhere).
void checkPcdData(const std::string& path, std::uint64_t data_at, const std::string& storage,
                  const std::vector<PcdField>& fields, std::uint64_t points,
                  const std::string& where);

}  // namespace slipfit::pipeline::detail
