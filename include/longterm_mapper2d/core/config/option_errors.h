#pragma once

#include <string>
#include <vector>

namespace longterm_mapper2d {

// Collects validation failures of nested option structs, each naming the parameter by its full
// path ("tracker/max_iterations: must be positive").
//
// Every options struct has two members:
//   template <class V> void Visit(V& v)  lists its fields, v("name_unit", field), and its nested
//                                        sections, v.Section("name", sub);
//   void Validate(OptionErrors& e) const  checks them with e.Require(...) and e.Section(...).
// The YAML and ROS parameter loaders and the config dump are written once against Visit.
class OptionErrors {
 public:
  void Require(bool condition, const std::string& field, const std::string& requirement) {
    if (!condition) errors_.push_back(prefix_ + field + ": " + requirement);
  }
  void Add(const std::string& message) { errors_.push_back(prefix_ + message); }

  template <class Options>
  void Section(const std::string& name, const Options& options) {
    const std::string saved = prefix_;
    prefix_ += name + "/";
    options.Validate(*this);
    prefix_ = saved;
  }

  bool empty() const { return errors_.empty(); }
  const std::vector<std::string>& errors() const { return errors_; }
  std::string ToString() const {
    std::string out;
    for (const auto& e : errors_) out += (out.empty() ? "" : "\n") + e;
    return out;
  }

 private:
  std::string prefix_;
  std::vector<std::string> errors_;
};

}  // namespace longterm_mapper2d
