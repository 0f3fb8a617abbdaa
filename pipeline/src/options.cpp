#include "slipfit/pipeline/options.h"

#include "slipfit/pipeline/errors.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

namespace slipfit::pipeline {

namespace {

/// Whether \a name ends in \a extension, ignoring case (".PLY" is a PLY).
bool endsIn(const std::string& name, const std::string& extension) {
  return name.size() > extension.size() &&
         std::equal(extension.rbegin(), extension.rend(), name.rbegin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) ==
                  std::tolower(static_cast<unsigned char>(b));
         });
}

std::string number(double v) {
  return parameterNumberText(v);
}

std::string vec3Text(const Eigen::Vector3f& v) {
  return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]";
}

double parseNumber(const YAML::Node& node, const Option& option, bool integer) {
  const std::string text = OptionSet::scalarText(node, option);
  std::istringstream is(text);
  is.imbue(std::locale::classic());
  double value = 0.0;
  if (integer) {
    long long i = 0;
    if (!(is >> i) || is.peek() != std::char_traits<char>::eof())
      throw OptionValueError("expected an integer, got '" + text + "'");
    value = static_cast<double>(i);
  } else {
    is >> value;
    if (is.fail() || is.peek() != std::char_traits<char>::eof())
      throw OptionValueError("expected a number, got '" + text + "'");
  }
  if (!std::isfinite(value))
    throw OptionValueError("expected a finite number, got '" + text + "'");
  option.checkRange(value);
  return value;
}

Eigen::Vector3d parseVec3d(const YAML::Node& node, const Option& option) {
  if (!node.IsSequence() || node.size() != 3)
    throw OptionValueError("expected a list of three numbers like [0, 0, 1]");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i)
    v[i] = parseNumber(node[i], option, false);
  return v;
}

Eigen::Vector3f parseVec3(const YAML::Node& node, const Option& option) {
  return parseVec3d(node, option).cast<float>();
}

}  // namespace

std::string Option::rangeText() const {
  if (!choices_.empty()) {
    std::string s = "one of ";
    for (std::size_t i = 0; i < choices_.size(); ++i)
      s += (i ? ", " : "") + choices_[i];
    return s;
  }
  return range_.text();
}

void Option::checkRange(double value) const {
  if (!range_.contains(value))
    throw OptionValueError("must be in " + rangeText() + ", got " + number(value));
}

std::string OptionSet::scalarText(const YAML::Node& node, const Option& option) {
  if (!node.IsScalar())
    throw OptionValueError("expected a single " + option.type() + " value, got a " +
                           (node.IsSequence() ? "list"
                            : node.IsMap()    ? "map"
                                              : "null"));
  // A NUL would cut every message (and file name) that holds the value at that point.
  if (node.Scalar().find('\0') != std::string::npos)
    throw OptionValueError("holds a NUL character (\\0), which no name or number can hold");
  return node.Scalar();
}

void OptionSet::throwNotAChoice(const std::string& text, const Option& option) {
  throw OptionValueError("'" + text + "' is not " + option.rangeText());
}

Option& OptionSet::push(std::string name, std::string type, std::string default_text,
                        std::string help, Option::Parser parser) {
  options_.push_back(std::make_unique<Option>(std::move(name), std::move(type),
                                              std::move(default_text), std::move(help),
                                              std::move(parser)));
  return *options_.back();
}

Option& OptionSet::add(std::string name, int& field, std::string help) {
  return push(std::move(name), "int", std::to_string(field), std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                const double v = parseNumber(node, option, true);
                if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
                  throw OptionValueError("integer out of range");
                field = static_cast<int>(v);
              });
}

Option& OptionSet::add(std::string name, double& field, std::string help) {
  return push(std::move(name), "float", number(field), std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                field = parseNumber(node, option, false);
              });
}

Option& OptionSet::add(std::string name, double& field, double scale, std::string help) {
  return push(std::move(name), "float", number(field / scale), std::move(help),
              [&field, scale](const YAML::Node& node, const Option& option) {
                field = parseNumber(node, option, false) * scale;
              });
}

Option& OptionSet::add(std::string name, std::uint64_t& field, std::string help) {
  return push(std::move(name), "uint", std::to_string(field), std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                const std::string text = scalarText(node, option);
                std::istringstream is(text);
                unsigned long long v = 0;
                if (text.empty() || text[0] == '-' || !(is >> v) ||
                    is.peek() != std::char_traits<char>::eof())
                  throw OptionValueError("expected a non-negative integer, got '" + text + "'");
                option.checkRange(static_cast<double>(v));
                field = v;
              });
}

Option& OptionSet::add(std::string name, bool& field, std::string help) {
  return push(std::move(name), "bool", field ? "true" : "false", std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                const std::string text = scalarText(node, option);
                if (text == "true" || text == "yes" || text == "on")
                  field = true;
                else if (text == "false" || text == "no" || text == "off")
                  field = false;
                else
                  throw OptionValueError("expected true or false, got '" + text + "'");
              });
}

Option& OptionSet::add(std::string name, std::string& field, std::string help) {
  return push(
      std::move(name), "string", field.empty() ? "\"\"" : field, std::move(help),
      [&field](const YAML::Node& node, const Option& option) {
        field = scalarText(node, option);
        if (field.empty() && !option.allowsEmpty())
          throw OptionValueError("must not be empty");
        if (option.isFileName() &&
            (field.find_first_of("/\\") != std::string::npos || field == "." || field == ".."))
          throw OptionValueError(
              "must be a plain file name inside output.dir (no directory part), got '" + field +
              "'");
        const std::vector<std::string>& extensions = option.fileExtensions();
        if (!extensions.empty() && !field.empty() &&
            std::none_of(extensions.begin(), extensions.end(),
                         [&](const std::string& ext) { return endsIn(field, ext); })) {
          std::string listed;
          for (std::size_t k = 0; k < extensions.size(); ++k)
            listed += (k == 0 ? "" : k + 1 == extensions.size() ? " or " : ", ") + extensions[k];
          throw OptionValueError("'" + field + "' must end in " + listed +
                                 ": slipfit writes this file in that format");
        }
      });
}

Option& OptionSet::add(std::string name, std::optional<int>& field, std::string help) {
  return push(std::move(name), "int", field ? std::to_string(*field) : "unset", std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                field = static_cast<int>(parseNumber(node, option, true));
              });
}

Option& OptionSet::add(std::string name, std::optional<double>& field, std::string help) {
  return push(std::move(name), "float", field ? number(*field) : "unset", std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                field = parseNumber(node, option, false);
              });
}

Option& OptionSet::add(std::string name, std::optional<double>& field, std::string_view automatic,
                       std::string help) {
  return push(
      std::move(name), "float", field ? number(*field) : std::string(automatic), std::move(help),
      [&field, automatic = std::string(automatic)](const YAML::Node& node, const Option& option) {
        const std::string text = scalarText(node, option);
        if (text == automatic) {
          field.reset();
          return;
        }
        std::istringstream is(text);
        is.imbue(std::locale::classic());
        double value = 0.0;
        if (!(is >> value) || is.peek() != std::char_traits<char>::eof())
          throw OptionValueError("expected a number or '" + automatic + "', got '" + text + "'");
        field = parseNumber(node, option, false);
      });
}

Option& OptionSet::add(std::string name, std::optional<std::size_t>& field, std::string help) {
  return push(std::move(name), "int", field ? std::to_string(*field) : "unset", std::move(help),
              [&field](const YAML::Node& node, const Option& option) {
                const double v = parseNumber(node, option, true);
                if (v < 0)
                  throw OptionValueError("expected a count (0 or more), got " + number(v));
                field = static_cast<std::size_t>(v);
              });
}

Option& OptionSet::add(std::string name, Eigen::Vector3f& field, std::string help) {
  return push(
      std::move(name), "vec3", vec3Text(field), std::move(help),
      [&field](const YAML::Node& node, const Option& option) { field = parseVec3(node, option); });
}

Option& OptionSet::add(std::string name, std::optional<Eigen::Vector3f>& field, std::string help) {
  return push(
      std::move(name), "vec3", field ? vec3Text(*field) : "unset", std::move(help),
      [&field](const YAML::Node& node, const Option& option) { field = parseVec3(node, option); });
}

Option& OptionSet::add(std::string name, Eigen::Vector3d& field, std::string help) {
  return push(
      std::move(name), "vec3", vec3Text(field.cast<float>()), std::move(help),
      [&field](const YAML::Node& node, const Option& option) { field = parseVec3d(node, option); });
}

Option& OptionSet::add(std::string name, std::optional<Eigen::Vector3d>& field, std::string help) {
  return push(
      std::move(name), "vec3", field ? vec3Text(field->cast<float>()) : "unset", std::move(help),
      [&field](const YAML::Node& node, const Option& option) { field = parseVec3d(node, option); });
}

const Option* OptionSet::find(std::string_view name) const {
  for (const auto& o : options_)
    if (o->name() == name)
      return o.get();
  return nullptr;
}

std::string OptionSet::namesText() const {
  std::string s;
  for (const auto& o : options_)
    s += (s.empty() ? "" : ", ") + o->name();
  return s;
}

}  // namespace slipfit::pipeline
