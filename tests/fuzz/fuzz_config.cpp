// libFuzzer target: the YAML config loader and validator on arbitrary text. Every outcome is a
// config or an exception of the documented kinds; anything else (a crash, a sanitizer report, an
// unexpected exception type) is a finding.
#include "slipfit/pipeline/config.h"
#include "slipfit/pipeline/errors.h"

#include <pcl/exceptions.h>

#include <unistd.h>
#include <cstdint>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path =
      "/tmp/slipfit_fuzz_config_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    (void)slipfit::pipeline::loadConfig(path, {});
  } catch (const slipfit::pipeline::ConfigError&) {
  } catch (const slipfit::pipeline::RunError&) {
  } catch (const pcl::PCLException&) {
  }
  return 0;
}
