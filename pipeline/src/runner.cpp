#include "slipfit/pipeline/runner.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/progress.h"

#include <pcl/exceptions.h>

#include <sys/resource.h>

#include <chrono>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace slipfit::pipeline {

namespace {

/// The process's peak resident set so far (Linux reports ru_maxrss in KiB).
long peakMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

}  // namespace

namespace {
/// Swallows everything (for --quiet).
class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
};
}  // namespace

std::vector<std::string> runPipeline(PipelineConfig& config, const RunOptions& options,
                                     std::ostream& report_stream) {
  NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  std::ostream& report = options.quiet ? null_stream : report_stream;
  Progress progress(!options.quiet);
  const std::size_t steps = config.stages.size() + 2;

  PointData data;
  unsigned input_bits = 0;
  if (!config.input.path.empty()) {
    progress.begin(1, steps, "read " + config.input.path);
    ReadReport read;
    data = readCloud(config.input.path, config.input.nan, &read);
    progress.end();
    report << "input: " << config.input.path << ": " << data.size() << " points";
    if (read.dropped)
      report << " (" << read.dropped << " non-finite dropped)";
    report << ", normals: " << (read.normals ? "yes" : "no");
    if (!read.extra_fields.empty())
      report << ", fields: " << read.extra_fields;
    report << "\n";
    input_bits = data.available();
  }
  const std::string flow = checkDataFlow(config, input_bits);
  if (!flow.empty())
    throw RunError(config.path + ": " + flow);

  // Stages may add files (meshes); everything is renamed into place only at the end.
  OutputFiles outputs(config.output.dir);
  for (std::size_t i = 0; i < config.stages.size(); ++i) {
    auto& s = config.stages[i];
    // A stage's report lines wait until its progress line is finished, so the two never mix.
    std::ostringstream stage_report;
    RunContext context{progress, stage_report, config.settings.threads, config.settings.seed,
                       &outputs};
    progress.begin(i + 2, steps, s.tag + " (" + s.type + ")");
    const auto start = std::chrono::steady_clock::now();
    try {
      s.stage->run(data, context);
    } catch (const RunError& e) {
      throw RunError("stage '" + s.tag + "' (" + s.type + "): " + e.what());
    } catch (const pcl::PCLException& e) {
      throw RunError("stage '" + s.tag + "' (" + s.type + "): " + e.what());
    } catch (const std::bad_alloc&) {
      throw RunError("stage '" + s.tag + "' (" + s.type + "): out of memory");
    }
    progress.end();
    report << stage_report.str();
    report << "  " << s.tag << ": " << std::fixed << std::setprecision(2)
           << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
           << " s, peak memory " << peakMegabytes() << " MB\n"
           << std::defaultfloat;
  }

  data.expandToFull();  // a subsampled analysis is written for every input point
  progress.begin(steps, steps, "write " + config.output.dir);
  if (!config.output.cloud.empty())
    outputs.add(config.output.cloud, [&](const std::string& path) {
      writeCloudPly(data, path, config.output.format == PlyEncoding::binary);
    });
  const auto written = outputs.commit();
  progress.end();
  for (const auto& path : written)
    report << "wrote " << path << "\n";
  return written;
}

}  // namespace slipfit::pipeline
