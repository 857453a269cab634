#include "longterm_mapper2d/core/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

namespace longterm_mapper2d {
namespace {

std::string ErrnoText() { return std::strerror(errno); }

std::string FolderOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

}  // namespace

Status WriteFileAtomically(const std::string& path, const std::string& bytes) {
  if (path.empty()) return Status::Error("cannot write a file with an empty path");
  // mkstemp needs a mutable template; the temporary lives beside the target.
  std::string temp_template = path + ".tmp.XXXXXX";
  std::vector<char> temp_path(temp_template.begin(), temp_template.end());
  temp_path.push_back('\0');
  const int fd = ::mkstemp(temp_path.data());
  if (fd < 0) {
    return Status::Error("cannot create a temporary file for '" + path + "': " + ErrnoText());
  }
  const std::string temp_name(temp_path.data());
  auto fail = [&](const std::string& what) {
    const std::string reason = ErrnoText();
    ::close(fd);
    ::unlink(temp_name.c_str());
    return Status::Error("cannot write '" + path + "': " + what + ": " + reason);
  };

  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail("write failed");
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) return fail("flush to disk failed");
  // mkstemp creates the file with mode 0600; give it the usual permissions of a data file
  // (reading the umask would need umask(), which is not thread-safe).
  if (::fchmod(fd, 0644) != 0) return fail("setting permissions failed");
  if (::close(fd) != 0) {
    const std::string reason = ErrnoText();
    ::unlink(temp_name.c_str());
    return Status::Error("cannot write '" + path + "': close failed: " + reason);
  }
  if (std::rename(temp_name.c_str(), path.c_str()) != 0) {
    const std::string reason = ErrnoText();
    ::unlink(temp_name.c_str());
    return Status::Error("cannot write '" + path + "': rename failed: " + reason);
  }
  // The rename must reach the disk too, or a power cut could bring back the old name (best
  // effort: a file system may refuse to sync a folder; the data itself is already synced).
  const int folder = ::open(FolderOf(path).c_str(), O_RDONLY | O_DIRECTORY);
  if (folder >= 0) {
    ::fsync(folder);
    ::close(folder);
  }
  return Status::Ok();
}

Status MakeDirectories(const std::string& directory) {
  std::string partial;
  for (std::size_t i = 0; i <= directory.size(); ++i) {
    if (i == directory.size() || directory[i] == '/') {
      if (!partial.empty() && ::mkdir(partial.c_str(), 0755) != 0 && errno != EEXIST) {
        return Status::Error("cannot create folder '" + partial + "': " + ErrnoText());
      }
    }
    if (i < directory.size()) partial += directory[i];
  }
  return Status::Ok();
}

StatusOr<std::string> ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error("cannot open '" + path + "'");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return Status::Error("error while reading '" + path + "'");
  return buffer.str();
}

}  // namespace longterm_mapper2d
