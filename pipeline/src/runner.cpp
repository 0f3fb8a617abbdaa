#include "slipfit/pipeline/runner.h"

#include "null_buffer.h"

#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/output_files.h"
#include "slipfit/pipeline/progress.h"

#include <pcl/exceptions.h>

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <thread>

namespace slipfit::pipeline {

namespace {

/// Peak resident memory of one step, sampled from /proc/self/statm every 5 ms by a thread
/// (without /proc: the process's peak so far). The kernel's own high-water mark is left alone,
/// so external tools (/usr/bin/time, bench/) still see the run's true peak.
class StepMemory {
 public:
  StepMemory()
      : sampler_([this] {
          while (!stop_) {
            update();
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
          }
        }) {}
  ~StepMemory() {
    stop_ = true;
    sampler_.join();
  }
  StepMemory(const StepMemory&) = delete;
  StepMemory& operator=(const StepMemory&) = delete;

  void reset() { peak_ = residentKiB(); }
  long peakKiB() {
    update();
    return peak_;
  }
  /// Resident memory before any data: the program and its libraries.
  long startKiB() const { return start_; }

 private:
  static long residentKiB() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    if (statm >> pages >> resident)
      return resident * (sysconf(_SC_PAGESIZE) / 1024);
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;
  }
  void update() {
    const long now = residentKiB();
    long seen = peak_.load();
    while (now > seen && !peak_.compare_exchange_weak(seen, now)) {
    }
  }

  const long start_ = residentKiB();
  std::atomic<long> peak_{start_};
  std::atomic<bool> stop_{false};
  std::thread sampler_;  // last: starts once the members above exist
};

/// "name: 1.23 s, peak memory 456 MB (78 B per point)" for a step that started at \a start; the
/// bytes per point count what the step holds above the program's own memory at start.
void reportStep(std::ostream& report, const std::string& name,
                std::chrono::steady_clock::time_point start, StepMemory& memory,
                std::size_t points) {
  const long kib = memory.peakKiB();
  report << "  " << name << ": " << std::fixed << std::setprecision(2)
         << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
         << " s, peak memory " << kib / 1024 << " MB";
  if (points > 0)
    report << " (" << std::setprecision(0)
           << static_cast<double>(std::max(0L, kib - memory.startKiB())) * 1024.0 / points
           << " B per point)";
  report << "\n" << std::defaultfloat;
}

}  // namespace

namespace {
/// Points whose given normal is missing (NaN, inf or zero in the file): when no stage reads the
/// given normals before one estimates them, they keep their place (the estimate replaces the
/// missing normal); when a stage reads them, input.nan decides — skip drops those points (the
/// count is returned), error stops naming the first point and the stage.
std::size_t settleMissingNormals(const PipelineConfig& config, const ReadReport& read,
                                 PointData& data) {
  if (!read.normals_missing)
    return 0;
  const ConfiguredStage* user = firstUserOfInputNormals(config);
  if (!user)
    return 0;
  if (config.input.nan == NanPolicy::error)
    throw RunError("input '" + config.input.path + "': point " +
                   std::to_string(read.first_missing_normal) +
                   " has a zero or non-finite normal (" + std::to_string(read.normals_missing) +
                   " such points) and stage '" + user->tag + "' (" + user->type +
                   ") reads the given normals; set input.nan: skip to drop such points");
  std::vector<char> keep(data.size());
  for (std::size_t i = 0; i < data.size(); ++i)
    keep[i] = std::isfinite((*data.cloud)[i].normal_x) ? 1 : 0;
  data.keepOnly(keep);
  if (data.size() == 0)
    throw RunError("input '" + config.input.path + "': none of its points has a finite normal, " +
                   "and stage '" + user->tag + "' (" + user->type + ") reads the given normals");
  return read.normals_missing;
}

}  // namespace

std::vector<std::string> runPipeline(PipelineConfig& config, const RunOptions& options,
                                     std::ostream& report_stream) {
  checkConfigFiles(config);  // nothing runs when an output would replace the input
  detail::NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  std::ostream& report = options.quiet ? null_stream : report_stream;
  for (const std::string& done : removeLeftovers(config.output.dir, config.input.path))
    report << "output: " << done << ", left by a killed run\n";
  Progress progress(!options.quiet);
  const std::size_t steps = config.stages.size() + 2;

  PointData data;
  unsigned input_bits = 0;
  StepMemory memory;
  std::size_t points = 0;  // of the input: bytes per point are per input point
  if (!config.input.path.empty()) {
    progress.begin(1, steps, "read " + config.input.path);
    memory.reset();
    const auto start = std::chrono::steady_clock::now();
    ReadReport read;
    data = readCloud(config.input.path, config.input.nan, &read);
    if (!data.sensor && config.input.sensor) {
      const auto& v = *config.input.sensor;
      SensorPose pose;  // unorganized: no rows and columns
      pose.origin = Eigen::Vector3d(v[0], v[1], v[2]) - data.frame.shift;
      pose.orientation = Eigen::Quaterniond(v[3], v[4], v[5], v[6]).normalized();
      data.sensor = pose;
    }
    progress.end();
    points = data.size();
    const std::size_t normals_dropped = settleMissingNormals(config, read, data);
    report << "input: " << config.input.path << ": " << data.size() << " points";
    if (read.dropped)
      report << " (" << read.dropped << " with a non-finite coordinate dropped)";
    if (normals_dropped)
      report << " (" << normals_dropped << " without a finite normal dropped)";
    report << ", normals: " << (read.normals ? "yes" : "no");
    if (read.normals_missing && !normals_dropped) {
      const bool estimated =
          std::any_of(config.stages.begin(), config.stages.end(),
                      [](const auto& s) { return (s.stage->flow().produces & kNormals) != 0; });
      report << " (" << read.normals_missing << " missing" << (estimated ? ": re-estimated" : "")
             << ")";
    }
    if (!read.extra_fields.empty())
      report << ", fields: " << read.extra_fields;
    if (data.sensor) {
      const SensorPose& s = *data.sensor;
      if (s.height > 1)
        report << ", organized " << s.width << " x " << s.height;
      const Eigen::Vector3d at = s.origin + data.frame.shift;
      report << ", sensor at (" << at.x() << ", " << at.y() << ", " << at.z() << ")";
    }
    report << "\n";
    if (data.frame.shift != Eigen::Vector3d::Zero()) {
      const Eigen::Vector3d& t = data.frame.shift;
      report << std::setprecision(17) << "input: global shift (" << t.x() << ", " << t.y() << ", "
             << t.z() << ") subtracted: double coordinates up to " << read.largest_coordinate
             << std::setprecision(6)
             << " would lose their detail in float; outputs are written in the input's frame\n";
    }
    reportStep(report, "read", start, memory, points);
    input_bits = data.available();
  }
  const std::string flow = checkDataFlow(config, input_bits);
  if (!flow.empty())
    throw RunError(config.path + ": " + flow);

  // Stages may add files (meshes); everything is renamed into place only at the end.
  OutputFiles outputs(config.output.dir);
  outputs.announceCommit(options.final_outputs);
  if (!config.input.path.empty())
    outputs.protect(config.input.path);
  for (std::size_t i = 0; i < config.stages.size(); ++i) {
    auto& s = config.stages[i];
    // A stage's report lines wait until its progress line is finished, so the two never mix.
    std::ostringstream stage_report;
    RunContext context{progress,
                       stage_report,
                       config.settings.threads,
                       config.settings.seed,
                       &outputs,
                       !config.output.cloud.empty() || i + 1 < config.stages.size()};
    progress.begin(i + 2, steps, s.tag + " (" + s.type + ")");
    memory.reset();
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
    if (points == 0)
      points = data.full ? data.full->size() : data.size();  // a generated cloud
    reportStep(report, s.tag, start, memory, points);
  }

  progress.begin(steps, steps, "write " + config.output.dir);
  memory.reset();
  const auto start = std::chrono::steady_clock::now();
  data.expandToFull();  // a subsampled analysis is written for every input point
  if (!config.output.cloud.empty())
    outputs.add(config.output.cloud, [&](const std::string& path) {
      std::string ext = std::filesystem::path(path).extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (ext == ".pcd")
        writeCloudPcd(data, path, config.output.format == PlyEncoding::binary);
      else
        writeCloudPly(data, path, config.output.format == PlyEncoding::binary);
    });
  const auto written = outputs.commit();
  progress.end();
  reportStep(report, "write", start, memory, points);
  for (const auto& path : written)
    report << "wrote " << path << "\n";
  return written;
}

}  // namespace slipfit::pipeline
