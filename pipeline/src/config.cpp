#include "slipfit/pipeline/config.h"

#include "slipfit/core/exceptions.h"
#include "slipfit/pipeline/errors.h"
#include "slipfit/pipeline/registry.h"

#include "file_checks.h"
#include "yaml_limits.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace slipfit::pipeline {

void InputSection::declare(OptionSet& o) {
  o.add("path", path, "Point cloud to read: .ply (ascii or binary) or .pcd.").required();
  o.add("nan", nan, kNanPolicyNames,
        "Points with a NaN/inf coordinate: 'skip' (the default, as PCL's tools) drops them and "
        "reports how many (organized scans mark missing depth with NaN); 'error' stops. A point "
        "whose given normal is NaN/inf/zero keeps its place with the normal missing when a stage "
        "estimates normals before any stage reads them; when a stage reads the given normals, "
        "'skip' drops it and 'error' stops.");
}

void OutputSection::declare(OptionSet& o) {
  o.add("dir", dir, "Directory for the outputs; created if missing.");
  o.add("format", format, kPlyEncodingNames, "Encoding of the output cloud, PLY or PCD.");
  o.add("cloud", cloud,
        "File name of the output cloud inside dir: .ply, or .pcd in PCL's conventions — "
        "organized (width × height, NaN where no point) with the sensor's VIEWPOINT when the "
        "cloud is a sensor's view (empty: none, when the stages write what is wanted).")
      .allowEmpty()
      .fileName(std::vector<std::string>{".ply", ".pcd"});
}

void TilingSection::declare(OptionSet& o) {
  o.add("size", size, "auto",
        "Edge of a tile's core in the cloud's units: the cloud is streamed into square tiles of "
        "the x-y plane (split further where a core holds over max_points), each run through the "
        "stages on its own and the segments joined across tiles (docs/TILING.md); 0: one "
        "untiled run; auto: the edge at which a tile of the cloud's mean density over its x-y "
        "extent holds max_points, rounded up to 1, 2 or 5 times a power of ten (one more read "
        "of the input; the report says what it chose).")
      .unit("units")
      .atLeast(0.0);
  o.add("buffer", buffer,
        "Width of the band around each core that the tile also reads, where segments of "
        "neighbouring tiles are matched; at least a few neighbourhood radii, under size / 2 "
        "(0: a tenth of size).")
      .unit("units")
      .atLeast(0.0);
  o.add("max_points", max_points,
        "The most points a tile's core may hold: a denser tile is split into quarters, and "
        "those again, while they stay wider than twice the buffer, so that memory follows this "
        "count whatever the density (a tile run takes about 300 bytes a point; 0: no limit).")
      .unit("points");
  o.add("workdir", workdir,
        "Directory of the tiles and the per-tile results (kept for a rerun to resume; empty: "
        "<output.dir>/tiles).")
      .allowEmpty();
}

void RunSettings::declare(OptionSet& o) {
  o.add("threads", threads,
        "Worker threads for parallel stages (a tiled run: tiles run at a time, one thread each); "
        "0 uses every core.")
      .range(0, 1024);
  o.add("seed", seed, "Seed of every random choice, for reproducible runs.");
}

namespace {

/// The sections of a config; every other top-level key is an option of RunSettings.
const std::set<std::string> kSections = {"input", "stages", "output", "tiling"};

/// RunSettings' options, for their names (bound to a settings object of their own).
const OptionSet& settingsOptions() {
  static RunSettings names_only;
  static const OptionSet options = [] {
    OptionSet o;
    names_only.declare(o);
    return o;
  }();
  return options;
}

class Loader {
 public:
  Loader(std::string path, const std::vector<std::string>& overrides) : path_(std::move(path)) {
    try {
      detail::checkReadableFile(path_, "config '" + path_ + "': ", "a YAML file");
    } catch (const RunError& e) {
      fail(e.what());
    }
    std::ifstream in(path_, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    detail::checkYamlLimits(text.str(), path_);
    try {
      root_ = YAML::Load(text.str());
    } catch (const YAML::ParserException& e) {
      fail(at(e.mark) + "YAML syntax error: " + e.msg);
    } catch (const YAML::Exception& e) {
      fail("config '" + path_ + "': " + e.what());
    }
    if (!root_.IsMap())
      fail(path_ + ": the config must be a YAML map with input, stages, output");
    refuseMergeKeys(root_);
    for (const auto& o : overrides)
      applyOverride(o);
  }

  PipelineConfig load() {
    PipelineConfig config;
    config.path = path_;
    const YAML::Node& root = root_;
    for (const auto& kv : root) {
      const std::string key = kv.first.Scalar();
      if (!kSections.count(key) && !settingsOptions().find(key))
        fail(at(kv.first.Mark()) + "unknown top-level key '" + key +
             "'; valid keys: input, stages, output, tiling, " + settingsOptions().namesText());
    }
    {
      OptionSet options;
      config.settings.declare(options);
      applyMap(root, options, "", "top level", /*skip=*/kSections);
    }
    // Without an input section the first stage must make the points (e.g. torus_sampling).
    if (root["input"])
      parseSection(root["input"], "input", [&](OptionSet& o) { config.input.declare(o); });
    if (root["output"])
      parseSection(root["output"], "output", [&](OptionSet& o) { config.output.declare(o); });
    if (root["tiling"])
      parseSection(root["tiling"], "tiling", [&](OptionSet& o) { config.tiling.declare(o); });
    const std::optional<double>& size = config.tiling.size;
    if (size && *size > 0.0 && *size < std::numeric_limits<double>::min())
      fail(keyPlace("tiling", "size", root["tiling"]["size"].Mark()) +
           "section 'tiling': size is too small to divide coordinates by (under 2.2e-308)");
    if (size && *size > 0.0 && config.tiling.bufferWidth(*size) >= 0.5 * *size)
      fail(keyPlace("tiling", "buffer", root["tiling"]["buffer"].Mark()) +
           "section 'tiling': buffer must be under size / 2");
    const YAML::Node stages = root["stages"];
    if (!stages)
      fail(path_ + ": missing 'stages' list");
    if (!stages.IsSequence())
      fail(at(stages.Mark()) + "'stages' must be a list of stages");

    std::set<std::string> tags;
    for (const auto& node : stages) {
      ConfiguredStage s = parseStage(node);
      if (!tags.insert(s.tag).second)
        fail(s.where + "stage tag '" + s.tag + "' is used twice; give each stage its own tag");
      config.stages.push_back(std::move(s));
    }
    const std::string flow = checkDataFlow(config, root["input"] ? kPoints | kNormals : 0u);
    if (!flow.empty())
      fail(path_ + ": " + flow);
    return config;
  }

 private:
  [[noreturn]] static void fail(const std::string& message) { throw ConfigError(message); }

  /// yaml-cpp reads a merge key (`<<: *defaults`) as an ordinary key named "<<": say so rather
  /// than report the keys it was meant to bring as missing.
  void refuseMergeKeys(const YAML::Node& node) const {
    if (node.IsMap()) {
      for (const auto& kv : node) {
        if (kv.first.IsScalar() && kv.first.Scalar() == "<<")
          fail(at(kv.first.Mark()) +
               "YAML merge keys ('<<') are not supported: write the keys out in full");
        refuseMergeKeys(kv.second);
      }
    } else if (node.IsSequence()) {
      for (const auto& item : node)
        refuseMergeKeys(item);
    }
  }

  std::string at(const YAML::Mark& mark) const {
    if (mark.is_null())
      return path_ + ": ";
    return path_ + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1) +
           ": ";
  }

  /// Location of a key: the --set that put it there, or its place in the file.
  std::string keyPlace(const std::string& section, const std::string& key,
                       const YAML::Mark& mark) const {
    const auto it = overrides_.find(section + "." + key);
    if (it != overrides_.end())
      return "--set " + it->second + ": ";
    return at(mark);
  }

  void applyOverride(const std::string& text) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0)
      fail("--set " + text + ": expected KEY=VALUE, e.g. --set normals.k=30");
    const std::string key = text.substr(0, eq);
    // The value is text, not YAML: no comment, tag, anchor or flow syntax is read in it (a
    // "#" or "!!" is part of a path). Quotes around the whole value are taken off ('' or "" is
    // the empty text). The option's type reads it: a vec3 option parses its [x, y, z] (applyMap).
    std::string raw = text.substr(eq + 1);
    if (raw.size() >= 2 && (raw.front() == '"' || raw.front() == '\'') && raw.back() == raw.front())
      raw = raw.substr(1, raw.size() - 2);
    const YAML::Node value(raw);
    const auto dot = key.find('.');
    if (dot == std::string::npos) {
      if (!settingsOptions().find(key)) {
        std::string names;
        for (const auto& o : settingsOptions().all())
          names += (names.empty() ? "" : " / ") + o->name();
        fail("--set " + text +
             ": expected SECTION.KEY (input.path, output.dir, tiling.size, TAG.OPTION) or " +
             names);
      }
      root_[key] = value;
      overrides_["." + key] = text;
      return;
    }
    const std::string section = key.substr(0, dot), option = key.substr(dot + 1);
    if (option.empty() || option.find('.') != std::string::npos)
      fail("--set " + text + ": expected SECTION.KEY with one dot");
    overrides_[section + "." + option] = text;
    if (section == "input" || section == "output" || section == "tiling") {
      if (!root_[section])
        root_[section] = YAML::Node(YAML::NodeType::Map);
      root_[section][option] = value;
      return;
    }
    std::string tags;
    for (auto node : root_["stages"]) {
      const std::string tag = stageTag(node);
      tags += (tags.empty() ? "" : ", ") + tag;
      if (tag == section) {
        node[option] = value;
        return;
      }
    }
    fail("--set " + text + ": no stage is tagged '" + section + "'; tags: " +
         (tags.empty() ? "none" : tags) + " (and the sections input, output, tiling)");
  }

  static std::string stageTag(const YAML::Node& node) {
    if (!node.IsMap())
      return "";
    const YAML::Node& c = node;
    if (c["tag"] && c["tag"].IsScalar())
      return c["tag"].Scalar();
    if (c["type"] && c["type"].IsScalar())
      return c["type"].Scalar();
    return "";
  }

  template <typename Declare>
  void parseSection(const YAML::Node& node, const std::string& name, Declare declare) {
    if (!node.IsMap())
      fail(at(node.Mark()) + "'" + name + "' must be a map of options");
    OptionSet options;
    declare(options);
    applyMap(node, options, name, "section '" + name + "'", {});
  }

  /// Parses every key of \a node into \a options; \a section names the override prefix.
  void applyMap(const YAML::Node& node, const OptionSet& options, const std::string& section,
                const std::string& who, const std::set<std::string>& skip) {
    std::set<std::string> seen, all_keys;
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      // yaml-cpp keeps both entries of a repeated key; the second would be silently ignored.
      if (!all_keys.insert(key).second)
        fail(keyPlace(section, key, kv.first.Mark()) + who + ": key '" + key + "' is given twice");
      if (skip.count(key))
        continue;
      const Option* option = options.find(key);
      const std::string place = keyPlace(section, key, kv.first.Mark());
      if (!option)
        fail(place + who + ": unknown key '" + key + "'; valid keys: " + options.namesText());
      try {
        const bool from_set = overrides_.count(section + "." + key) != 0;
        if (from_set && option->type() == "vec3" && kv.second.IsScalar()) {
          YAML::Node list;
          try {
            list = YAML::Load(kv.second.Scalar());
          } catch (const YAML::Exception&) {
            throw OptionValueError("expected a list of three numbers like [0, 0, 1], got '" +
                                   kv.second.Scalar() + "'");
          }
          option->parse(list);
        } else {
          option->parse(kv.second);
        }
      } catch (const OptionValueError& e) {
        fail(keyPlace(section, key, kv.second.Mark()) + who + ": key '" + key + "': " + e.what());
      }
      seen.insert(key);
    }
    for (const auto& o : options.all())
      if (o->isRequired() && !seen.count(o->name()))
        fail(at(node.Mark()) + who + ": missing required key '" + o->name() + "'");
  }

  ConfiguredStage parseStage(const YAML::Node& node) {
    ConfiguredStage s;
    s.where = at(node.Mark());
    if (!node.IsMap())
      fail(s.where + "each stage must be a map with at least 'type'");
    const YAML::Node type = node["type"];
    if (!type || !type.IsScalar())
      fail(s.where + "stage without 'type'; known stages: " + knownStagesText());
    s.type = type.Scalar();
    const StageInfo* info = findStage(s.type);
    if (!info)
      fail(at(type.Mark()) + "unknown stage type '" + s.type +
           "'; known stages: " + knownStagesText());
    s.tag = node["tag"] ? node["tag"].Scalar() : s.type;
    if (s.tag.empty() || s.tag.find('.') != std::string::npos)
      fail(at(node["tag"].Mark()) + "stage tag '" + s.tag + "' must be non-empty and without dots");
    if (kSections.count(s.tag))
      fail(at(node["tag"] ? node["tag"].Mark() : node.Mark()) + "stage tag '" + s.tag +
           "' is the name of a section (--set " + s.tag +
           ".KEY sets the section); give the stage another tag");
    s.stage = info->make();
    OptionSet options;
    s.stage->declare(options);
    const std::string who = "stage '" + s.tag + "' (" + s.type + ")";
    applyMap(node, options, s.tag, who, {"type", "tag"});
    try {
      s.stage->prepare();
    } catch (const OptionValueError& e) {
      fail(s.where + who + ": " + e.what());
    } catch (const pcl::PCLException& e) {
      fail(s.where + who + ": " + e.what());
    }
    return s;
  }

  std::string path_;
  YAML::Node root_;
  std::map<std::string, std::string> overrides_;  // "section.key" -> the --set text
};

}  // namespace

PipelineConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides) {
  try {
    Loader loader(path, overrides);
    return loader.load();
  } catch (const YAML::Exception& e) {
    // Anything yaml-cpp throws past the checks above is still a config problem.
    throw ConfigError(path + ": " + e.what());
  }
}

void checkConfigFiles(const PipelineConfig& config) {
  namespace fs = std::filesystem;
  if (!config.input.path.empty())
    detail::checkReadableFile(config.input.path,
                              "input '" + config.input.path + "': ", "a point cloud file");
  detail::checkOutputDir(config.output.dir);
  std::vector<std::pair<std::string, std::string>> outputs;  // name, who writes it
  if (!config.output.cloud.empty())
    outputs.emplace_back(config.output.cloud, "output.cloud");
  for (const auto& s : config.stages)
    for (const auto& name : s.stage->outputFiles())
      outputs.emplace_back(name, "stage '" + s.tag + "' (" + s.type + ")");
  std::map<std::string, std::string> by_name;
  for (const auto& [name, who] : outputs) {
    const auto [it, fresh] = by_name.emplace(name, who);
    if (!fresh)
      throw ConfigError(config.path + ": " + it->second + " and " + who + " both write '" + name +
                        "' in output.dir; give each its own name");
    const fs::path final_path = fs::path(config.output.dir) / name;
    std::error_code ec;
    if (!config.input.path.empty() && fs::equivalent(final_path, config.input.path, ec))
      throw RunError("output '" + final_path.string() + "' (" + who + ") is the input '" +
                     config.input.path +
                     "': nothing is written over it; choose another name or output.dir");
  }
}

std::string checkDataFlow(const PipelineConfig& config, unsigned input_bits) {
  unsigned available = input_bits;
  for (const auto& s : config.stages) {
    const DataFlow flow = s.stage->flow();
    const unsigned missing = flow.consumes & ~available;
    if (missing) {
      return "stage '" + s.tag + "' (" + s.type + ") needs " + dataBitsText(missing) + ": " +
             (input_bits ? "the input has none" : "there is no input section") +
             " and no earlier stage produces them";
    }
    available |= flow.produces;
  }
  if (!(available & kPoints))
    return "no input section and no stage that makes points (e.g. torus_sampling)";
  return "";
}

const ConfiguredStage* firstUserOfInputNormals(const PipelineConfig& config) {
  for (const auto& s : config.stages) {
    const DataFlow flow = s.stage->flow();
    if (flow.consumes & kNormals)
      return &s;
    if (flow.produces & kNormals)
      return nullptr;
  }
  return nullptr;
}

}  // namespace slipfit::pipeline
