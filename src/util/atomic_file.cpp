#include "skin/util/atomic_file.hpp"

#include <atomic>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <unistd.h>

#include "skin/util/error.hpp"

namespace skin::io {

namespace fs = std::filesystem;

std::string extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

namespace {
std::string temporary_name(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  const fs::path p(path);
  // Same directory (so that rename is atomic), hidden, unique per process and call; the
  // extension is kept because some writers choose the format from it.
  return (p.parent_path() / ("." + p.stem().string() + ".tmp" + std::to_string(::getpid()) + "-" +
                             std::to_string(counter++) + p.extension().string()))
      .string();
}
}  // namespace

void write_via_temporary(const std::string& path, const std::function<void(const std::string&)>& write) {
  if (path.empty()) throw InputError("output: an empty file name was given");
  const fs::path p(path);
  if (fs::is_directory(p)) throw InputError(path + ": is a directory, not a file name");
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  if (!fs::is_directory(dir))
    throw InputError(path + ": cannot write: directory '" + dir.string() + "' does not exist");
  const std::string tmp = temporary_name(path);
  try {
    write(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, p, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot write: " + ec.message());
  }
}

void write_file_atomic(const std::string& path, const std::string& content) {
  write_via_temporary(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot open for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw InputError(path + ": write failed (disk full?)");
  });
}

}  // namespace skin::io
