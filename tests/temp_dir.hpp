#pragma once
// A temporary directory of a test's own: mkdtemp makes the name unique across processes, so
// tests run in parallel by CTest, or by concurrent builds sharing /tmp, never share it. Removed
// with everything in it when the object goes out of scope (also when an assertion returns early).
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace skin::test {

class TempDir {
 public:
  // Creates <system temp>/<prefix>_XXXXXX.
  explicit TempDir(const std::string& prefix) {
    std::string name = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (::mkdtemp(name.data()) == nullptr) throw std::runtime_error("mkdtemp failed: " + name);
    path_ = name;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace skin::test
