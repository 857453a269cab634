#pragma once

#include <string>

namespace longterm_mapper2d {
namespace test_support {

// A fresh folder under the system's temporary directory (prefix_XXXXXX), removed with everything
// in it when the object goes: tests that write files leave nothing behind.
class ScopedTempDir {
 public:
  explicit ScopedTempDir(const std::string& prefix = "ltm_test");
  ~ScopedTempDir();
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;

  // Empty if the folder could not be made.
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace test_support
}  // namespace longterm_mapper2d
