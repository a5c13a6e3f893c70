#pragma once
// Reads a YAML file and turns every problem into a ConfigError that names file, line and key.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

#include "hunav/config_error.hpp"

namespace hunav {

class YamlReader {
 public:
  explicit YamlReader(std::string path);  // throws ConfigError when missing or not YAML
  YamlReader(std::string path, const YAML::Node& root) : path_(std::move(path)), root_(root) {}

  const std::string& path() const { return path_; }
  const YAML::Node& root() const { return root_; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key, const std::string& what) const;

  // The child `key` of mapping `map`; `where` is the dotted path of `map` for messages.
  YAML::Node child(const YAML::Node& map, const std::string& key, const std::string& where, bool required) const;

  template <class T>
  T get(const YAML::Node& map, const std::string& key, const std::string& where) const {
    return convert<T>(child(map, key, where, true), join(where, key));
  }
  template <class T>
  T get(const YAML::Node& map, const std::string& key, const std::string& where, const T& fallback) const {
    const YAML::Node n = child(map, key, where, false);
    return n ? convert<T>(n, join(where, key)) : fallback;
  }

  template <class T>
  T convert(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, std::string("expected ") + typeName<T>());
    try {
      T value = n.as<T>();
      if constexpr (std::is_floating_point_v<T>) {
        if (!std::isfinite(value)) fail(n, key, "expected a finite number");
      }
      return value;
    } catch (const YAML::BadConversion&) {
      fail(n, key, std::string("expected ") + typeName<T>() + ", got '" + n.Scalar() + "'");
    }
  }

  static std::string join(const std::string& where, const std::string& key) {
    return where.empty() ? key : where + "." + key;
  }
  // 1-based line of a node, or 0 when unknown.
  static int lineOf(const YAML::Node& n);

 private:
  template <class T>
  static const char* typeName() {
    if constexpr (std::is_same_v<T, bool>)
      return "true or false";
    else if constexpr (std::is_integral_v<T>)
      return "an integer";
    else if constexpr (std::is_floating_point_v<T>)
      return "a number";
    else
      return "a string";
  }

  std::string path_;
  YAML::Node root_;
};

}  // namespace hunav
