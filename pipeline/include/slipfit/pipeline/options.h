#pragma once
/// \file Declared options: each stage declares each option once (name, bound field, default,
/// unit, range, help); parsing, validation, `slipfit describe` and the docs all read that one
/// declaration (the PDAL addArgs model).

#include "slipfit/core/name_table.h"
#include "slipfit/core/parameter_declaration.h"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace YAML {
class Node;
}

namespace slipfit::pipeline {

class Option {
 public:
  using Parser = std::function<void(const YAML::Node&, const Option&)>;

  Option(std::string name, std::string type, std::string default_text, std::string help,
         Parser parser)
      : name_(std::move(name)),
        type_(std::move(type)),
        default_(std::move(default_text)),
        help_(std::move(help)),
        parser_(std::move(parser)) {}

  /// Unit of the value (e.g. "m", "neighbors", "deg"); shown by describe.
  Option& unit(std::string unit) {
    unit_ = std::move(unit);
    return *this;
  }
  /// Inclusive numeric range.
  Option& range(double lo, double hi) { return lowBound(lo, false).highBound(hi, false); }
  /// The range of a library declaration (ParameterDeclaration::range).
  Option& range(const ParameterRange& range) {
    range_ = range;
    return *this;
  }
  /// Exclusive lower bound (value > lo).
  Option& above(double lo) { return lowBound(lo, true); }
  /// Inclusive lower bound.
  Option& atLeast(double lo) { return lowBound(lo, false); }
  /// Exclusive upper bound (value < hi).
  Option& below(double hi) { return highBound(hi, true); }
  /// Inclusive upper bound.
  Option& atMost(double hi) { return highBound(hi, false); }
  /// The option must be given.
  Option& required() {
    required_ = true;
    return *this;
  }
  Option& choices(std::vector<std::string> names) {
    choices_ = std::move(names);
    return *this;
  }

  const std::string& name() const { return name_; }
  const std::string& type() const { return type_; }
  const std::string& defaultText() const { return default_; }
  const std::string& unit() const { return unit_; }
  const std::string& help() const { return help_; }
  const std::vector<std::string>& choices() const { return choices_; }
  bool isRequired() const { return required_; }
  /// The numeric bounds (unset: none on that side); each excludes its value when open.
  std::optional<double> low() const { return range_.low; }
  std::optional<double> high() const { return range_.high; }
  bool lowOpen() const { return range_.low_open; }
  bool highOpen() const { return range_.high_open; }
  /// "[3, 10000]", "(0, inf)", "one of knn, radius" or "" when unconstrained.
  std::string rangeText() const;

  /// Converts \a node into the bound field; throws OptionValueError with what is wrong.
  void parse(const YAML::Node& node) const { parser_(node, *this); }
  /// Throws OptionValueError when \a value is outside the declared range (or not finite).
  void checkRange(double value) const;
  /// A string option that may be set to "" (meaning "none"); strings must not be empty otherwise.
  Option& allowEmpty() {
    allow_empty_ = true;
    return *this;
  }
  bool allowsEmpty() const { return allow_empty_; }
  /// A string option naming an output file: a plain file name inside output.dir (no directory
  /// part, not "." or ".."), checked when the config is read, so `validate` refuses it too.
  /// A file name in the output directory (no path); with \a extension, one that ends in it (the
  /// format slipfit writes the file in: a cloud named .pcd would still be PLY).
  Option& fileName(std::string extension = "") {
    return fileName(std::vector<std::string>{std::move(extension)});
  }
  /// A file name ending in one of \a extensions (the formats slipfit can write it in).
  Option& fileName(std::vector<std::string> extensions) {
    file_name_ = true;
    extensions_ = std::move(extensions);
    extensions_.erase(std::remove(extensions_.begin(), extensions_.end(), std::string()),
                      extensions_.end());
    return *this;
  }
  bool isFileName() const { return file_name_; }
  /// The extensions a file name may end in; empty: any.
  const std::vector<std::string>& fileExtensions() const { return extensions_; }

 private:
  Option& lowBound(double lo, bool open) {
    range_.setLow(lo, open);
    return *this;
  }
  Option& highBound(double hi, bool open) {
    range_.setHigh(hi, open);
    return *this;
  }

  std::string name_, type_, default_, help_, unit_;
  std::vector<std::string> extensions_;
  ParameterRange range_;
  bool required_ = false;
  bool allow_empty_ = false;
  bool file_name_ = false;
  std::vector<std::string> choices_;
  Parser parser_;
};

/// The options of one stage (or of the input/output sections), in declaration order.
class OptionSet {
 public:
  Option& add(std::string name, int& field, std::string help);
  Option& add(std::string name, double& field, std::string help);
  /// A number the user gives in one unit and the field holds in another: field = value × \a scale
  /// (degrees into radians: kDegree); range and default are the user's.
  Option& add(std::string name, double& field, double scale, std::string help);
  Option& add(std::string name, bool& field, std::string help);
  Option& add(std::string name, std::string& field, std::string help);
  Option& add(std::string name, std::uint64_t& field, std::string help);
  Option& add(std::string name, std::optional<int>& field, std::string help);
  Option& add(std::string name, std::optional<double>& field, std::string help);
  /// A number, or the word \a automatic, which leaves \a field unset for the program to choose.
  Option& add(std::string name, std::optional<double>& field, std::string_view automatic,
              std::string help);
  Option& add(std::string name, std::optional<std::size_t>& field, std::string help);
  Option& add(std::string name, Eigen::Vector3f& field, std::string help);
  Option& add(std::string name, Eigen::Vector3d& field, std::string help);
  Option& add(std::string name, std::optional<Eigen::Vector3f>& field, std::string help);
  Option& add(std::string name, std::optional<Eigen::Vector3d>& field, std::string help);

  /// An enumeration bound through its one name table.
  template <typename E, std::size_t N>
  Option& add(std::string name, E& field,
              const std::array<std::pair<E, std::string_view>, N>& names, std::string help) {
    auto parser = [&field, names](const YAML::Node& node, const Option& option) {
      field = valueNamed(names, scalarText(node, option), option);
    };
    return push(std::move(name), "enum", std::string(nameIn(names, field)), std::move(help), parser)
        .choices(namesOf(names, {}));
  }

  /// An enumeration the stage may choose itself: \a automatic (e.g. "auto") leaves \a field
  /// unset, every other name is a value of the table.
  template <typename E, std::size_t N>
  Option& add(std::string name, std::optional<E>& field, std::string_view automatic,
              const std::array<std::pair<E, std::string_view>, N>& names, std::string help) {
    auto parser = [&field, names, automatic = std::string(automatic)](const YAML::Node& node,
                                                                      const Option& option) {
      const std::string text = scalarText(node, option);
      if (text == automatic)
        field.reset();
      else
        field = valueNamed(names, text, option);
    };
    return push(std::move(name), "enum", std::string(field ? nameIn(names, *field) : automatic),
                std::move(help), parser)
        .choices(namesOf(names, {std::string(automatic)}));
  }

  /// Binds every parameter that \a parameters declares (its static forEachParameter): name, help,
  /// unit, range and the unit's scale come from the library's one declaration.
  /// \a renames: (declared name, option name) where the stage's options need another name.
  template <typename Parameters>
  void bind(Parameters& parameters,
            std::initializer_list<std::pair<std::string_view, std::string_view>> renames = {}) {
    Parameters::forEachParameter(parameters, [&](auto& field, ParameterDeclaration d,
                                                 const auto&... names) {
      for (const auto& [declared, option] : renames)
        if (d.name == declared)
          d.name = option;
      Option& option = bindDeclared(field, d, names...).unit(std::string(d.unit)).range(d.range);
      if (d.required)
        option.required();
    });
  }

  const Option* find(std::string_view name) const;
  const std::vector<std::unique_ptr<Option>>& all() const { return options_; }
  /// "a, b, c": the names, for error messages.
  std::string namesText() const;

  /// Helpers shared by the parsers.
  static std::string scalarText(const YAML::Node& node, const Option& option);
  [[noreturn]] static void throwNotAChoice(const std::string& text, const Option& option);

  /// The value of \a names called \a text; throws OptionValueError listing the choices if none.
  template <typename E, std::size_t N>
  static E valueNamed(const std::array<std::pair<E, std::string_view>, N>& names,
                      const std::string& text, const Option& option) {
    for (const auto& [value, t] : names)
      if (t == text)
        return value;
    throwNotAChoice(text, option);
  }
  /// \a first, then the names of the table, in its order.
  template <typename E, std::size_t N>
  static std::vector<std::string> namesOf(
      const std::array<std::pair<E, std::string_view>, N>& names, std::vector<std::string> first) {
    for (const auto& [value, text] : names)
      first.emplace_back(text);
    return first;
  }

 private:
  template <typename T>
  Option& bindDeclared(T& field, const ParameterDeclaration& d) {
    if constexpr (std::is_same_v<T, double>)
      return add(std::string(d.name), field, d.scale, std::string(d.help));
    else
      return add(std::string(d.name), field, std::string(d.help));
  }
  template <typename E, std::size_t N>
  Option& bindDeclared(E& field, const ParameterDeclaration& d,
                       const std::array<std::pair<E, std::string_view>, N>& names) {
    return add(std::string(d.name), field, names, std::string(d.help));
  }
  template <typename E, std::size_t N>
  Option& bindDeclared(std::optional<E>& field, const ParameterDeclaration& d,
                       std::string_view automatic,
                       const std::array<std::pair<E, std::string_view>, N>& names) {
    return add(std::string(d.name), field, automatic, names, std::string(d.help));
  }

  Option& push(std::string name, std::string type, std::string default_text, std::string help,
               Option::Parser parser);
  std::vector<std::unique_ptr<Option>> options_;
};

}  // namespace slipfit::pipeline
