#include "skin/util/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

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

std::string temporary_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  // Same directory (so that rename is atomic), hidden, unique per process and call; the
  // extension is kept because some writers choose the format from it.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += target.extension().string();
  return (target.parent_path() / name).string();
}

// Follows symbolic links (relative targets resolve against the link's directory) to the path
// that is really written. A loop or a chain deeper than 40 is an error.
fs::path resolve_links(const std::string& path) {
  fs::path p(path);
  for (int depth = 0; depth < 40; ++depth) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(p, ec);
    if (ec || !fs::is_symlink(st)) return p;
    const fs::path t = fs::read_symlink(p, ec);
    if (ec) throw InputError(path + ": cannot read the symbolic link: " + ec.message());
    p = t.is_absolute() ? t : p.parent_path() / t;
  }
  throw InputError(path + ": cannot write: too many levels of symbolic links");
}

// Writes all of `data` to an open descriptor; false on error (errno set).
bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

void write_in_place(const std::string& shown, const fs::path& target, const std::string& data) {
  const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(shown + ": cannot open for writing: " + std::strerror(errno));
  const bool ok = write_all(fd, data.data(), data.size());
  const int err = errno;
  ::close(fd);
  if (!ok) throw InputError(shown + ": write failed: " + std::strerror(err));
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

void write_via_temporary(const std::string& path, const std::function<void(const std::string&)>& write) {
  if (path.empty()) throw InputError("output: an empty file name was given");
  const bool to_stdout = path == "-";
  const fs::path target = to_stdout ? fs::path() : resolve_links(path);
  std::error_code ec;
  const fs::file_status st = to_stdout ? fs::file_status() : fs::status(target, ec);
  const bool exists = !to_stdout && fs::exists(st);
  if (exists && fs::is_directory(st)) throw InputError(path + ": is a directory, not a file name");
  // FIFOs, devices and standard output are written in place (after the writer has finished).
  const bool in_place = to_stdout || (exists && !fs::is_regular_file(st));
  fs::path tmp_dir;
  if (in_place) {
    tmp_dir = fs::temp_directory_path(ec);
    if (ec) tmp_dir = "/tmp";
  } else {
    tmp_dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    if (!fs::is_directory(tmp_dir))
      throw InputError(path + ": cannot write: directory '" + tmp_dir.string() + "' does not exist");
  }
  const fs::path name = to_stdout ? fs::path("stdout") : target.filename();
  const std::string tmp = temporary_name(tmp_dir / name);
  auto cleanup = [&] {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  };
  try {
    write(tmp);
  } catch (...) {
    cleanup();
    throw;
  }
  if (in_place) {
    const std::string data = read_file(tmp);
    cleanup();
    if (to_stdout) {
      if (!write_all(STDOUT_FILENO, data.data(), data.size()))
        throw InputError("standard output: write failed: " + std::string(std::strerror(errno)));
      return;
    }
    write_in_place(path, target, data);
    return;
  }
  if (exists) {
    // Keep the replaced file's permission bits.
    fs::permissions(tmp, fs::status(target, ec).permissions(), fs::perm_options::replace, ec);
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    cleanup();
    throw InputError(path + ": cannot write: " + ec.message());
  }
}

void write_file_atomic(const std::string& path, const std::string& content) {
  write_via_temporary(path, [&](const std::string& tmp) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) throw InputError(path + ": cannot open for writing: " + std::strerror(errno));
    const bool ok = write_all(fd, content.data(), content.size());
    const int err = errno;
    const bool closed = ::close(fd) == 0;
    if (!ok || !closed)
      throw InputError(path + ": write failed: " + std::strerror(ok ? errno : err));
  });
}

}  // namespace skin::io
