#include "holo/core/config.hpp"

#include <algorithm>
#include <sstream>

namespace holo {

namespace {
std::string describeNode(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list of " + std::to_string(node.size());
  return "a map";
}
std::string locate(const YAML::Node& node) {
  const auto mark = node.Mark();
  if (mark.is_null()) return {};
  return " (line " + std::to_string(mark.line + 1) + ")";
}
}  // namespace

ConfigNode ConfigNode::loadFile(const std::filesystem::path& path) {
  try {
    return ConfigNode(YAML::LoadFile(path.string()), path.string(), "");
  } catch (const YAML::BadFile&) {
    throw InputError(path.string(), "", "a readable YAML file", "cannot open");
  } catch (const YAML::ParserException& e) {
    throw InputError(
        path.string(),
        "line " + std::to_string(e.mark.line + 1) + ", column " + std::to_string(e.mark.column + 1),
        "valid YAML", e.msg);
  }
}

ConfigNode ConfigNode::parse(const std::string& text, const std::string& origin) {
  try {
    return ConfigNode(YAML::Load(text), origin, "");
  } catch (const YAML::ParserException& e) {
    throw InputError(origin, "line " + std::to_string(e.mark.line + 1), "valid YAML", e.msg);
  }
}

void ConfigNode::rejectUnknownKeys(const std::vector<std::string>& known) const {
  std::string list;
  for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
  if (!isMap()) fail("a map with the fields " + list);
  for (const std::string& key : keys())
    if (std::find(known.begin(), known.end(), key) == known.end())
      (*this)[key].fail("one of the fields " + list, "an unknown field '" + key + "'");
}

std::filesystem::path ConfigNode::pathBesideFile(const std::filesystem::path& value) const {
  if (value.is_absolute() || file_.empty()) return value;
  std::error_code ec;
  const std::filesystem::path file(file_);
  return std::filesystem::is_regular_file(file, ec) ? file.parent_path() / value : value;
}

bool ConfigNode::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

ConfigNode ConfigNode::operator[](const std::string& key) const {
  const std::string child = path_.empty() ? key : path_ + "." + key;
  if (!node_.IsMap()) fail("a map with the field '" + key + "'", describeNode(node_));
  if (!has(key)) throw InputError(file_, child, "a value (the field is required)", "nothing");
  return ConfigNode(node_[key], file_, child);
}

ConfigNode ConfigNode::operator[](std::size_t index) const {
  const std::string child = path_ + "[" + std::to_string(index) + "]";
  if (!node_.IsSequence() || index >= node_.size())
    throw InputError(file_, child, "an element (list too short)", describeNode(node_));
  return ConfigNode(node_[index], file_, child);
}

std::optional<ConfigNode> ConfigNode::find(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

std::size_t ConfigNode::size() const {
  return node_.IsSequence() ? node_.size() : 0;
}

std::vector<std::string> ConfigNode::keys() const {
  std::vector<std::string> out;
  if (node_.IsMap())
    for (const auto& kv : node_) {
      // YAML allows any node as a key ("? [a, b]: x"); a configuration's keys are names.
      if (!kv.first.IsScalar())
        fail("a map whose keys are names", "a key that is a " + describeNode(kv.first));
      out.push_back(kv.first.Scalar());
    }
  return out;
}

void ConfigNode::fail(const std::string& expected, const std::string& got) const {
  throw InputError(file_, path_.empty() ? "(top level)" : path_ + locate(node_), expected,
                   got.empty() ? describeNode(node_) : got);
}

template <>
std::string ConfigNode::as<std::string>() const {
  if (!node_.IsScalar()) fail("a string");
  return node_.Scalar();
}

template <>
bool ConfigNode::as<bool>() const {
  bool value = false;
  if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, value)) fail("true or false");
  return value;
}

template <>
int ConfigNode::as<int>() const {
  int value = 0;
  if (!node_.IsScalar() || !YAML::convert<int>::decode(node_, value)) fail("an integer");
  return value;
}

template <>
double ConfigNode::as<double>() const {
  double value = 0;
  if (!node_.IsScalar() || !YAML::convert<double>::decode(node_, value) || !std::isfinite(value))
    fail("a finite number");
  return value;
}

template <>
float ConfigNode::as<float>() const {
  return static_cast<float>(as<double>());
}

template <>
vec2 ConfigNode::as<vec2>() const {
  if (!node_.IsSequence() || node_.size() != 2) fail("a list of 2 numbers");
  return {(*this)[0].as<float>(), (*this)[1].as<float>()};
}

template <>
vec3 ConfigNode::as<vec3>() const {
  if (!node_.IsSequence() || node_.size() != 3) fail("a list of 3 numbers [x, y, z]");
  return {(*this)[0].as<float>(), (*this)[1].as<float>(), (*this)[2].as<float>()};
}

float ConfigNode::getInRange(const std::string& key, float fallback, float lo, float hi) const {
  if (!has(key)) return fallback;
  const ConfigNode child = (*this)[key];
  const float value = child.as<float>();
  if (value < lo || value > hi) {
    std::ostringstream expected;
    expected << "a number in [" << lo << ", " << hi << "]";
    child.fail(expected.str());
  }
  return value;
}

}  // namespace holo
