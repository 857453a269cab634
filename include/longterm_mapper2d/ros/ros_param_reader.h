#pragma once

#include <ros/node_handle.h>

#include <set>
#include <string>
#include <vector>

#include "longterm_mapper2d/core/common/status.h"
#include "longterm_mapper2d/core/config/option_errors.h"

namespace longterm_mapper2d_ros {

// Fills an options struct (the core's Visit protocol) from the parameter server under a
// NodeHandle, remembering every key it knows so that unknown (misspelled) parameters can be
// reported. Values of the wrong type are errors naming the parameter.
class RosParamReader {
 public:
  RosParamReader(const ros::NodeHandle& nh, std::string prefix)
      : nh_(nh), prefix_(std::move(prefix)) {}

  template <typename T>
  void operator()(const char* key, T& value) {
    const std::string name = prefix_ + key;
    known_->insert(nh_.resolveName(name));
    if (!nh_.hasParam(name)) return;
    if constexpr (std::is_same_v<T, int> || std::is_same_v<T, bool> ||
                  std::is_same_v<T, std::string>) {
      if (!nh_.getParam(name, value)) errors_->push_back(name + ": wrong type");
    } else if constexpr (std::is_floating_point_v<T>) {
      double d;
      int i;
      if (nh_.getParam(name, d)) {
        value = d;
      } else if (nh_.getParam(name, i)) {
        value = i;
      } else {
        errors_->push_back(name + ": wrong type (expected a number)");
      }
    } else {
      int i;
      if (nh_.getParam(name, i)) {
        value = static_cast<T>(i);
      } else {
        errors_->push_back(name + ": wrong type (expected an integer)");
      }
    }
  }

  template <class Options>
  void Section(const char* key, Options& options) {
    RosParamReader child(nh_, prefix_ + key + "/");
    child.known_ = known_;
    child.errors_ = errors_;
    options.Visit(child);
  }

  // Checks the values, and that every parameter under the node's namespace is one it knows.
  longterm_mapper2d::Status Finish(const std::vector<std::string>& also_known = {}) const;

  std::shared_ptr<std::set<std::string>> known_ = std::make_shared<std::set<std::string>>();
  std::shared_ptr<std::vector<std::string>> errors_ = std::make_shared<std::vector<std::string>>();

 private:
  ros::NodeHandle nh_;
  std::string prefix_;
};

// Loads `options` from the private namespace of `nh`, validating them.
template <class Options>
longterm_mapper2d::Status LoadRosParams(const ros::NodeHandle& nh, const std::string& prefix,
                                        Options& options, RosParamReader& reader) {
  RosParamReader scoped(nh, prefix);
  scoped.known_ = reader.known_;
  scoped.errors_ = reader.errors_;
  options.Visit(scoped);
  longterm_mapper2d::OptionErrors validation;
  options.Validate(validation);
  for (const auto& e : validation.errors()) reader.errors_->push_back(prefix + e);
  return longterm_mapper2d::Status::Ok();
}

}  // namespace longterm_mapper2d_ros
