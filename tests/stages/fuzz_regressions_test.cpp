// Inputs the fuzzers found (tests/fuzz/regressions) and the kernels' seed corpus, replayed through
// the same checks as the fuzz target on every build, so that a fixed crash stays fixed without
// clang. (A reader crash became a case of tests/bad_inputs/catalogue.yaml instead.)
#include "kernel_checks.h"
#include "paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace slipfit {
namespace {

TEST(FuzzRegressions, KernelInputsStayFiniteOrRefused) {
  namespace fs = std::filesystem;
  std::size_t replayed = 0;
  for (const char* dir : {"/tests/fuzz/regressions", "/tests/fuzz/corpus/kernels"})
    for (const auto& entry : fs::directory_iterator(std::string(testing::kSourceDir) + dir)) {
      const std::string name = entry.path().filename().string();
      if (dir[13] == 'r' && name.rfind("kernels_", 0) != 0)
        continue;
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      SCOPED_TRACE(name);
      fuzz::checkKernels(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      ++replayed;
    }
  EXPECT_GE(replayed, 5u);
}

}  // namespace
}  // namespace slipfit
