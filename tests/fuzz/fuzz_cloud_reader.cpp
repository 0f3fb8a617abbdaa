// libFuzzer target: the PLY, PCD and LAS readers as slipfit uses them (readCloud), and the
// row-range reader (CloudStream), on arbitrary bytes. The first byte picks the extension: odd is
// .pcd, 2 modulo 4 is .las, another even value .ply (the seeds' leading bytes keep their reader).
// Either a cloud with finite coordinates comes back, or a RunError; the readers must never crash,
// and readCloud never hands out a non-finite point (CloudStream returns values as stored).
#include "slipfit/pipeline/cloud_io.h"
#include "slipfit/pipeline/cloud_stream.h"
#include "slipfit/pipeline/errors.h"

#include <unistd.h>
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0)
    return 0;
  static const std::string base = "/tmp/slipfit_fuzz_cloud_" + std::to_string(::getpid());
  const char* const extension = (data[0] & 1) ? ".pcd" : (data[0] % 4 == 2) ? ".las" : ".ply";
  const std::string path = base + extension;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  for (auto policy : {slipfit::pipeline::NanPolicy::error, slipfit::pipeline::NanPolicy::skip}) {
    try {
      const auto cloud = slipfit::pipeline::readCloud(path, policy);
      for (const auto& p : cloud.cloud->points)
        if (!p.getVector3fMap().allFinite())
          std::abort();  // the reader promised finite coordinates
    } catch (const slipfit::pipeline::RunError&) {
    }
  }
  try {
    slipfit::pipeline::CloudStream stream(path);
    Eigen::Matrix3Xd xyz;
    const std::uint64_t head = std::min<std::uint64_t>(stream.size(), 4096);
    stream.read(0, head, xyz);
    stream.read(head, std::min<std::uint64_t>(stream.size() - head, 16), xyz);
  } catch (const slipfit::pipeline::RunError&) {
  }
  try {  // whole rows, as the tiler copies them: every field of every row within the buffer
    slipfit::pipeline::CloudStream stream(path);
    std::vector<char> rows;
    const std::uint64_t head = std::min<std::uint64_t>(stream.size(), 4096);
    stream.readRecords(0, head, rows);
    if (rows.size() != head * stream.recordBytes())
      std::abort();
    for (const auto& f : stream.fields())
      if (f.offset + f.bytes > stream.recordBytes())
        std::abort();
  } catch (const slipfit::pipeline::RunError&) {
  }
  return 0;
}
