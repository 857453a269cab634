#include "longterm_mapper2d/ros/ros_param_reader.h"

#include <ros/param.h>

namespace longterm_mapper2d_ros {

longterm_mapper2d::Status RosParamReader::Finish(const std::vector<std::string>& also_known) const {
  std::vector<std::string> errors = *errors_;
  std::vector<std::string> names;
  if (ros::param::getParamNames(names)) {
    const std::string ns = nh_.getNamespace() + "/";
    for (const std::string& name : names) {
      if (name.rfind(ns, 0) != 0) continue;
      if (known_->count(name)) continue;
      bool allowed = false;
      for (const std::string& extra : also_known) allowed |= name == ns + extra;
      if (!allowed) errors.push_back(name + ": unknown parameter");
    }
  }
  if (errors.empty()) return longterm_mapper2d::Status::Ok();
  std::string message;
  for (const auto& e : errors) message += (message.empty() ? "" : "\n") + e;
  return longterm_mapper2d::Status::Error(message);
}

}  // namespace longterm_mapper2d_ros
