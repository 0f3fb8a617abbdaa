// libFuzzer target: the numeric kernels on arbitrary doubles (see kernel_checks.h).
#include "kernel_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  slipfit::fuzz::checkKernels(data, size);
  return 0;
}
