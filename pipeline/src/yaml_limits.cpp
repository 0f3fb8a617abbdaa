#include "yaml_limits.h"

#include "slipfit/pipeline/errors.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/exceptions.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <algorithm>
#include <sstream>
#include <vector>

namespace slipfit::pipeline::detail {

namespace {

/// What a node stands for once its aliases are expanded.
struct Extent {
  std::size_t nodes = 0, depth = 0;
};

class Counter : public YAML::EventHandler {
 public:
  explicit Counter(std::string path) : path_(std::move(path)) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    ++documents_;
    if (documents_ > 1)
      throw ConfigError(path_ + ":" + std::to_string(mark.line + 1) +
                        ": a second YAML document (after '---'); a config is one document");
    open_.assign(1, Extent{});
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                const std::string&) override {
    leaf(mark, anchor);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    // An alias inside the collection its anchor names would make the node its own descendant:
    // yaml-cpp builds that cycle, and every walk of it recurses until the stack overflows.
    if (anchor != YAML::NullAnchor &&
        std::find(anchor_of_.begin(), anchor_of_.end(), anchor) != anchor_of_.end())
      throw ConfigError(path_ + ":" + std::to_string(mark.line + 1) +
                        ": the YAML has an alias inside the anchor it names (a cycle)");
    const Extent e = anchor < anchors_.size() ? anchors_[anchor] : Extent{1, 0};
    add(mark, e);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    start(mark, anchor);
  }
  void OnSequenceEnd() override { end(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    start(mark, anchor);
  }
  void OnMapEnd() override { end(); }

 private:
  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor) {
    remember(anchor, Extent{1, 0});
    add(mark, Extent{1, 0});
  }
  void start(const YAML::Mark& mark, YAML::anchor_t anchor) {
    marks_.push_back(mark);
    anchor_of_.push_back(anchor);
    open_.push_back(Extent{1, 0});
    if (open_.size() - 1 > kDeepestYaml)
      fail(mark, "nests deeper than " + std::to_string(kDeepestYaml) + " levels");
  }
  void end() {
    const Extent done = open_.back();
    const YAML::Mark mark = marks_.back();
    const YAML::anchor_t anchor = anchor_of_.back();
    open_.pop_back();
    marks_.pop_back();
    anchor_of_.pop_back();
    const Extent e{done.nodes, done.depth + 1};
    remember(anchor, e);
    add(mark, e);
  }
  /// Adds a child of extent \a e to the innermost open node.
  void add(const YAML::Mark& mark, const Extent& e) {
    Extent& parent = open_.back();
    parent.nodes = std::min(parent.nodes + e.nodes, kMostYamlNodes + 1);
    parent.depth = std::max(parent.depth, e.depth);
    std::size_t total = 0;  // what the document holds so far, expanded
    for (const Extent& o : open_)
      total = std::min(total + o.nodes, kMostYamlNodes + 1);
    if (total > kMostYamlNodes)
      fail(mark, "expands to more than " + std::to_string(kMostYamlNodes) +
                     " nodes (its aliases copy what their anchors hold)");
    if (open_.size() - 1 + e.depth > kDeepestYaml)
      fail(mark, "nests deeper than " + std::to_string(kDeepestYaml) +
                     " levels once its aliases are expanded");
  }
  void remember(YAML::anchor_t anchor, const Extent& e) {
    if (anchor == YAML::NullAnchor)
      return;
    if (anchors_.size() <= anchor)
      anchors_.resize(anchor + 1, Extent{1, 0});
    anchors_[anchor] = e;
  }
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& what) const {
    throw ConfigError(path_ + ":" + std::to_string(mark.line + 1) + ": the YAML " + what +
                      "; a config is limited to " + std::to_string(kMostYamlNodes) + " nodes and " +
                      std::to_string(kDeepestYaml) + " levels");
  }

  std::string path_;
  int documents_ = 0;
  std::vector<Extent> open_, anchors_;
  std::vector<YAML::Mark> marks_;
  std::vector<YAML::anchor_t> anchor_of_;
};

}  // namespace

void checkYamlLimits(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  Counter counter(path);
  try {
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(counter)) {
    }
  } catch (const YAML::Exception&) {
    // a syntax error: the loader says it with its place
  }
}

}  // namespace slipfit::pipeline::detail
