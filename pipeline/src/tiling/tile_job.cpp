#include "tile_job.h"

#include "ply_rows.h"

#include "../digest.h"

#include "slipfit/pipeline/errors.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

namespace slipfit::pipeline::tiling {

namespace {

FieldAt needField(const std::vector<StreamField>& fields, const std::string& name,
                  const std::string& path) {
  const StreamField* f = findField(fields, name);
  if (!f)
    throw RunError("'" + path + "': no field " + name);
  return fieldAt(*f);
}

template <typename T>
void writeArray(std::ofstream& out, const std::vector<T>& values, const std::string& path) {
  writeOrFail(out, reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T), path);
}

template <typename T>
void readArray(std::ifstream& in, std::vector<T>& values, std::uint64_t n,
               const std::string& path) {
  values.resize(n);
  if (!in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(n * sizeof(T))))
    throw RunError("'" + path + "': truncated");
}

std::uint64_t readCount(std::ifstream& in, const std::string& path) {
  std::uint64_t n = 0;
  if (!in || !in.read(reinterpret_cast<char*>(&n), 8))
    throw RunError("'" + path + "': cannot be read");
  return n;
}

/// Throws RunError unless \a path holds \a header bytes and \a n records of \a record bytes
/// (checked before anything is allocated for a count read from the file).
void checkSize(const std::string& path, std::uint64_t header, std::uint64_t n,
               std::uint64_t record) {
  std::error_code ec;
  const std::uint64_t bytes = std::filesystem::file_size(path, ec);
  if (ec || n > (bytes - std::min(bytes, header)) / record || header + n * record != bytes)
    throw RunError("'" + path + "': its count says " + std::to_string(n) + " records of " +
                   std::to_string(record) + " bytes but the file holds " + std::to_string(bytes) +
                   " bytes (damaged; remove the tile's 'done' to run it again)");
}

constexpr const char* kDoneHeader = "slipfit tile run 1";

}  // namespace

void summariseTile(const std::string& run_dir, const std::string& segments_ply,
                   const std::string& primitives_yaml) {
  const std::string ply = run_dir + "/" + segments_ply;
  CloudStream in(ply);
  const auto& fields = in.fields();
  const FieldAt row_f = needField(fields, "tile_row", ply);
  const FieldAt core_f = needField(fields, "tile_core", ply);
  const FieldAt label_f = needField(fields, "label", ply);
  const FieldAt type_f = needField(fields, "primitive", ply);
  const FieldAt xyz[3] = {needField(fields, "x", ply), needField(fields, "y", ply),
                          needField(fields, "z", ply)};
  const FieldAt nxyz[3] = {needField(fields, "nx", ply), needField(fields, "ny", ply),
                           needField(fields, "nz", ply)};

  const auto n = static_cast<std::size_t>(in.size());
  std::vector<std::int32_t> label(n);
  std::vector<std::uint8_t> owned(n);
  std::vector<char> rows;
  in.readRecords(0, in.size(), rows);
  std::map<std::int32_t, TileSegment> segments;
  TileLabels shared;
  for (std::size_t k = 0; k < n; ++k) {
    const char* row = rows.data() + k * in.recordBytes();
    const double core = core_f.get(row);
    label[k] = static_cast<std::int32_t>(label_f.get(row));
    owned[k] = core != 0.0 ? 1 : 0;
    shared.owned += owned[k];
    if (core != 1.0) {  // held by a neighbour as well
      shared.rows.push_back(static_cast<std::uint64_t>(row_f.get(row)));
      shared.labels.push_back(label[k]);
      shared.core.push_back(owned[k]);
    }
    if (label[k] >= 0) {
      TileSegment& s = segments[label[k]];
      s.type = static_cast<int>(type_f.get(row));
      s.core_points += owned[k];
    }
  }
  // Per label: inlier distance and seed type from the tile's report.
  try {
    const YAML::Node report = YAML::LoadFile(run_dir + "/" + primitives_yaml);
    for (const auto& p : report["primitives"]) {
      const auto it = segments.find(p["label"].as<std::int32_t>());
      if (it == segments.end())
        continue;
      it->second.inlier_distance = p["inlier_distance"].as<double>();
      if (p["seed_slippage_type"])
        it->second.seed_slippage_type = p["seed_slippage_type"].as<std::string>();
    }
  } catch (const YAML::Exception& e) {
    throw RunError("'" + run_dir + "/" + primitives_yaml + "': " + e.what());
  }

  const std::string labels_path = run_dir + "/labels.bin";
  std::ofstream lo(labels_path, std::ios::binary | std::ios::trunc);
  const std::uint64_t header[2] = {shared.rows.size(), shared.owned};
  writeOrFail(lo, reinterpret_cast<const char*>(header), sizeof header, labels_path);
  writeArray(lo, shared.rows, labels_path);
  writeArray(lo, shared.labels, labels_path);
  writeArray(lo, shared.core, labels_path);
  lo.close();
  if (!lo)
    throw RunError("'" + labels_path + "': write failed (disk full?)");

  YAML::Emitter text;
  text.SetDoublePrecision(17);
  text << YAML::BeginSeq;
  for (const auto& [label, s] : segments)
    text << YAML::Flow << YAML::BeginSeq << label << s.type << s.core_points << s.inlier_distance
         << s.seed_slippage_type << YAML::EndSeq;
  text << YAML::EndSeq;
  std::ofstream so(run_dir + "/segments.yaml", std::ios::trunc);
  so << text.c_str() << "\n";
  so.close();
  if (!so)
    throw RunError("'" + run_dir + "/segments.yaml': write failed (disk full?)");

  // Every k-th core point of each label, k = ⌈core points / kSamplesPerSegment⌉.
  std::map<std::int32_t, std::uint64_t> seen;
  std::vector<std::int32_t> sample_labels;
  std::vector<double> sample_values, sample_weights;
  for (std::size_t k = 0; k < n; ++k) {
    if (!owned[k] || label[k] < 0)
      continue;
    const std::uint64_t total = segments[label[k]].core_points;
    const std::uint64_t stride = (total + kSamplesPerSegment - 1) / kSamplesPerSegment;
    if (seen[label[k]]++ % stride != 0)
      continue;
    const char* row = rows.data() + k * in.recordBytes();
    sample_labels.push_back(label[k]);
    for (const FieldAt& f : xyz)
      sample_values.push_back(f.get(row));
    for (const FieldAt& f : nxyz)
      sample_values.push_back(f.get(row));
    // This sample stands for the core points up to the next one.
    const std::uint64_t taken_before = (seen[label[k]] - 1) / stride;
    const std::uint64_t covers = std::min(stride, total - taken_before * stride);
    sample_weights.push_back(static_cast<double>(covers));
  }
  const std::string samples_path = run_dir + "/samples.bin";
  std::ofstream out(samples_path, std::ios::binary | std::ios::trunc);
  const std::uint64_t samples = sample_labels.size();
  writeOrFail(out, reinterpret_cast<const char*>(&samples), 8, samples_path);
  writeArray(out, sample_labels, samples_path);
  writeArray(out, sample_values, samples_path);
  writeArray(out, sample_weights, samples_path);
  out.close();
  if (!out)
    throw RunError("'" + samples_path + "': write failed (disk full?)");

  // `done` last: the size and digest of every file the merge reads.
  std::string record = std::string(kDoneHeader) + "\n";
  for (const std::string& name : {segments_ply, primitives_yaml, std::string("labels.bin"),
                                  std::string("segments.yaml"), std::string("samples.bin")}) {
    std::uint64_t digest = 0, bytes = 0;
    if (!detail::fileDigest(run_dir + "/" + name, digest, bytes))
      throw RunError("'" + run_dir + "/" + name + "': cannot be read back");
    record += name + " " + std::to_string(bytes) + " " + detail::hex(digest) + "\n";
  }
  std::ofstream done(run_dir + "/done", std::ios::trunc);
  done << record;
  done.close();
  if (!done)
    throw RunError("'" + run_dir + "/done': write failed (disk full?)");
}

TileLabels readTileLabels(const std::string& run_dir) {
  const std::string path = run_dir + "/labels.bin";
  std::ifstream in(path, std::ios::binary);
  const std::uint64_t n = readCount(in, path);
  checkSize(path, 16, n, 8 + 4 + 1);
  TileLabels l;
  l.owned = readCount(in, path);
  readArray(in, l.rows, n, path);
  readArray(in, l.labels, n, path);
  readArray(in, l.core, n, path);
  return l;
}

std::vector<TileSegment> readTileSegments(const std::string& run_dir) {
  const std::string path = run_dir + "/segments.yaml";
  std::vector<TileSegment> segments;
  try {
    for (const auto& s : YAML::LoadFile(path)) {
      const auto label = s[0].as<std::size_t>();
      if (label >= segments.size())
        segments.resize(label + 1);
      segments[label] = {s[1].as<int>(), s[2].as<std::uint64_t>(), s[3].as<double>(),
                         s[4].as<std::string>()};
    }
  } catch (const YAML::Exception& e) {
    throw RunError("'" + path + "': " + e.what());
  }
  return segments;
}

TileSamples readTileSamples(const std::string& run_dir) {
  const std::string path = run_dir + "/samples.bin";
  std::ifstream in(path, std::ios::binary);
  const std::uint64_t n = readCount(in, path);
  checkSize(path, 8, n, 4 + 6 * 8 + 8);
  TileSamples s;
  readArray(in, s.labels, n, path);
  std::vector<double> values;
  readArray(in, values, 6 * n, path);
  readArray(in, s.weights, n, path);
  s.points.resize(3, static_cast<Eigen::Index>(n));
  s.normals.resize(3, static_cast<Eigen::Index>(n));
  for (std::uint64_t k = 0; k < n; ++k)
    for (int a = 0; a < 3; ++a) {
      s.points(a, static_cast<Eigen::Index>(k)) = values[6 * k + static_cast<std::size_t>(a)];
      s.normals(a, static_cast<Eigen::Index>(k)) = values[6 * k + 3 + static_cast<std::size_t>(a)];
    }
  return s;
}

bool tileDone(const std::string& run_dir, std::string& why) {
  why.clear();
  std::ifstream in(run_dir + "/done");
  if (!in)
    return false;
  std::string line;
  if (!std::getline(in, line) || line != kDoneHeader) {
    why = "its 'done' is not a tile run's record";
    return false;
  }
  int files = 0;
  for (std::string name, digest; in >> name;) {
    std::uint64_t bytes = 0, found_digest = 0, found_bytes = 0;
    if (!(in >> bytes >> digest)) {
      why = "its 'done' is cut short";
      return false;
    }
    if (!detail::fileDigest(run_dir + "/" + name, found_digest, found_bytes)) {
      why = name + " is missing";
      return false;
    }
    if (found_bytes != bytes || detail::hex(found_digest) != digest) {
      why = name + " is not the file the run wrote (" +
            (found_bytes != bytes
                 ? std::to_string(found_bytes) + " bytes, written " + std::to_string(bytes)
                 : std::string("same size, other content")) +
            ")";
      return false;
    }
    ++files;
  }
  if (files != 5) {
    why = "its 'done' lists " + std::to_string(files) + " files, not 5";
    return false;
  }
  return true;
}

}  // namespace slipfit::pipeline::tiling
