#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d {

// Fills an options struct (see option_errors.h for the Visit protocol) from a YAML map. Keys that
// the struct does not have are errors, so a typo never goes unnoticed; missing keys keep their
// defaults; a value of the wrong type is an error naming the key.
class YamlOptionsReader {
 public:
  YamlOptionsReader(const YAML::Node& node, std::string prefix)
      : node_(node), prefix_(std::move(prefix)) {}

  template <typename T>
  void operator()(const char* key, T& value) {
    used_.insert(key);
    const YAML::Node child = node_[key];
    if (!child.IsDefined() || child.IsNull()) return;
    try {
      if constexpr (std::is_same_v<T, bool>) {
        value = child.as<bool>();
      } else if constexpr (std::is_integral_v<T>) {
        // Reject "2.5" for an integer instead of truncating it.
        const std::string text = child.as<std::string>();
        std::size_t consumed = 0;
        const long long parsed = std::stoll(text, &consumed);
        if (consumed != text.size()) throw YAML::Exception(YAML::Mark(), "not an integer");
        value = static_cast<T>(parsed);
      } else {
        value = child.as<T>();
      }
    } catch (const std::exception&) {
      errors_.push_back(prefix_ + key + ": cannot read value '" + Dump(child) + "'");
    }
  }

  template <class Options>
  void Section(const char* key, Options& options) {
    used_.insert(key);
    const YAML::Node child = node_[key];
    if (!child.IsDefined() || child.IsNull()) return;
    if (!child.IsMap()) {
      errors_.push_back(prefix_ + key + ": expected a map of parameters");
      return;
    }
    YamlOptionsReader reader(child, prefix_ + key + "/");
    options.Visit(reader);
    reader.ReportUnknownKeys();
    errors_.insert(errors_.end(), reader.errors_.begin(), reader.errors_.end());
  }

  void ReportUnknownKeys() {
    if (!node_.IsMap()) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (!used_.count(key)) errors_.push_back(prefix_ + key + ": unknown parameter");
    }
  }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  static std::string Dump(const YAML::Node& node) {
    std::stringstream ss;
    ss << node;
    return ss.str();
  }

  YAML::Node node_;
  std::string prefix_;
  std::set<std::string> used_;
  std::vector<std::string> errors_;
};

// Writes the effective options as YAML (for logs and for `--print-config`).
class YamlOptionsWriter {
 public:
  explicit YamlOptionsWriter(YAML::Emitter& out) : out_(out) {}
  template <typename T>
  void operator()(const char* key, T& value) {
    out_ << YAML::Key << key << YAML::Value << value;
  }
  template <class Options>
  void Section(const char* key, Options& options) {
    out_ << YAML::Key << key << YAML::Value << YAML::BeginMap;
    options.Visit(*this);
    out_ << YAML::EndMap;
  }

 private:
  YAML::Emitter& out_;
};

// Loads `options` from the YAML text, then validates. On error `options` may be partly filled;
// the status lists every problem, one per line.
template <class Options>
Status LoadOptionsFromYamlString(const std::string& yaml_text, Options& options) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const std::exception& e) {
    return Status::Error(std::string("invalid YAML: ") + e.what());
  }
  std::vector<std::string> errors;
  if (root.IsDefined() && !root.IsNull()) {
    if (!root.IsMap()) return Status::Error("invalid YAML: the top level must be a map");
    YamlOptionsReader reader(root, "");
    options.Visit(reader);
    reader.ReportUnknownKeys();
    errors = reader.errors();
  }
  OptionErrors validation;
  options.Validate(validation);
  errors.insert(errors.end(), validation.errors().begin(), validation.errors().end());
  if (errors.empty()) return Status::Ok();
  std::string message;
  for (const auto& e : errors) message += (message.empty() ? "" : "\n") + e;
  return Status::Error(message);
}

Status ReadTextFile(const std::string& path, std::string& text);

template <class Options>
Status LoadOptionsFromYamlFile(const std::string& path, Options& options) {
  std::string text;
  if (Status s = ReadTextFile(path, text); !s.ok()) return s;
  Status s = LoadOptionsFromYamlString(text, options);
  if (!s.ok()) return Status::Error(path + ":\n" + s.message());
  return s;
}

template <class Options>
std::string OptionsToYaml(const Options& options) {
  Options copy = options;
  YAML::Emitter out;
  out.SetDoublePrecision(10);  // 0.1 prints as 0.1, not 0.10000000000000001
  out << YAML::BeginMap;
  YamlOptionsWriter writer(out);
  copy.Visit(writer);
  out << YAML::EndMap;
  return out.c_str();
}

}  // namespace longterm_mapper2d
