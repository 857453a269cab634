#include "testing/temp_dir.h"

#include <stdlib.h>

#include <filesystem>
#include <system_error>
#include <vector>

namespace longterm_mapper2d {
namespace test_support {

ScopedTempDir::ScopedTempDir(const std::string& prefix) {
  std::error_code error;
  const std::string pattern =
      (std::filesystem::temp_directory_path(error) / (prefix + "_XXXXXX")).string();
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (::mkdtemp(buffer.data()) != nullptr) path_ = buffer.data();
}

ScopedTempDir::~ScopedTempDir() {
  if (path_.empty()) return;
  std::error_code ignored;  // a destructor reports nothing; a leftover folder is harmless
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace test_support
}  // namespace longterm_mapper2d
