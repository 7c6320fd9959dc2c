// YAML configuration with errors that name the file and the field. A ConfigNode remembers its
// file and its dotted path ("cameras[2].pose.position"), so every failed conversion says where.
#pragma once

#include <yaml-cpp/yaml.h>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/math.hpp"

namespace holo {

class ConfigNode {
 public:
  // Parses a file; a syntax error throws InputError with the line and column.
  static ConfigNode loadFile(const std::filesystem::path& path);
  // Parses text (embedded defaults); `origin` stands in for the file name in errors.
  static ConfigNode parse(const std::string& text, const std::string& origin);

  bool has(const std::string& key) const;
  ConfigNode operator[](const std::string& key) const;  // throws when missing
  ConfigNode operator[](std::size_t index) const;       // throws when out of range
  std::optional<ConfigNode> find(const std::string& key) const;
  std::size_t size() const;  // sequence length, or 0
  bool isSequence() const { return node_.IsSequence(); }
  bool isMap() const { return node_.IsMap(); }
  std::vector<std::string> keys() const;

  template <class T>
  T as() const;  // string, bool, int, float, double, vec2, vec3 (a 3-element list)
  template <class T>
  T get(const std::string& key, const T& fallback) const {
    return has(key) ? (*this)[key].as<T>() : fallback;
  }
  // Fails unless this is a map whose keys are all in `known` (a typo is an error, not a field
  // silently ignored); the error names the unknown field and lists the known ones.
  void rejectUnknownKeys(const std::vector<std::string>& known) const;
  // A float that must lie in [lo, hi]; the error names the range.
  float getInRange(const std::string& key, float fallback, float lo, float hi) const;

  const std::string& file() const { return file_; }
  // A path written in this configuration: a relative one is relative to the file's folder, so a
  // configuration moves along with its recordings, relic and calibration. Absolute paths, and
  // every path when the text came from no existing file, stay as written.
  std::filesystem::path pathBesideFile(const std::filesystem::path& value) const;
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& expected, const std::string& got = {}) const;
  const YAML::Node& yaml() const { return node_; }

 private:
  ConfigNode(YAML::Node node, std::string file, std::string path)
      : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}
  YAML::Node node_;
  std::string file_;
  std::string path_;
};

}  // namespace holo
