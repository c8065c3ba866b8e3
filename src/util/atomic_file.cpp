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
#include <iostream>
#include <system_error>

#include "skin/util/error.hpp"

namespace skin::util::io {

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

namespace {
// Where a path's data go: standard output, a FIFO or device written in place, or a regular file
// (new or replaced) behind any symbolic links.
struct Target {
  bool to_stdout = false, in_place = false, exists = false;
  fs::path path;  // the links' final target
};

Target find_target(const std::string& path) {
  if (path.empty()) throw InputError("output: an empty file name was given");
  Target t;
  if (path == "-") {
    t.to_stdout = t.in_place = true;
    return t;
  }
  t.path = resolve_links(path);
  std::error_code ec;
  const fs::file_status st = fs::status(t.path, ec);
  t.exists = fs::exists(st);
  if (t.exists && fs::is_directory(st)) throw InputError(path + ": is a directory, not a file name");
  t.in_place = t.exists && !fs::is_regular_file(st);
  return t;
}

// Writes complete data where the target says, in place (standard output, FIFO, device).
void write_data_in_place(const std::string& shown, const Target& t, const std::string& data) {
  if (!t.to_stdout) return write_in_place(shown, t.path, data);
  write_stdout(data);
}

// Writes `content` to a new file `tmp` (which must not exist).
void write_new_file(const std::string& shown, const std::string& tmp, const std::string& content) {
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw InputError(shown + ": cannot open for writing: " + std::strerror(errno));
  const bool ok = write_all(fd, content.data(), content.size());
  const int err = errno;
  const bool closed = ::close(fd) == 0;
  if (!ok || !closed) throw InputError(shown + ": write failed: " + std::strerror(ok ? errno : err));
}
}  // namespace

namespace {
[[noreturn]] void stdout_failed(int err) {
  throw InputError(std::string("output = '-': write failed") + (err != 0 ? ": " + std::string(std::strerror(err)) : ""));
}
}  // namespace

void flush_stdout() {
  errno = 0;
  std::cout.flush();
  int err = errno;
  const bool cout_ok = !std::cout.fail();  // (badbit stays from an earlier failed write)
  errno = 0;
  const bool stdio_ok = std::fflush(stdout) == 0 && std::ferror(stdout) == 0;
  if (errno != 0) err = errno;
  if (!cout_ok || !stdio_ok) stdout_failed(err);
}

void write_stdout(std::string_view data) {
  flush_stdout();
  if (!write_all(STDOUT_FILENO, data.data(), data.size())) stdout_failed(errno);
}

void write_via_temporary(const std::string& path, const std::function<void(const std::string&)>& write) {
  const Target t = find_target(path);
  std::error_code ec;
  fs::path tmp_dir;
  if (t.in_place) {
    // The writer needs a path: a temporary file elsewhere, copied in place once complete.
    tmp_dir = fs::temp_directory_path(ec);
    if (ec) tmp_dir = "/tmp";
  } else {
    tmp_dir = t.path.parent_path().empty() ? fs::path(".") : t.path.parent_path();
    if (!fs::is_directory(tmp_dir))
      throw InputError(path + ": cannot write: directory '" + tmp_dir.string() + "' does not exist");
  }
  const std::string tmp = temporary_name(tmp_dir / (t.to_stdout ? fs::path("stdout") : t.path.filename()));
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
  if (t.in_place) {
    const std::string data = read_file(tmp);
    cleanup();
    write_data_in_place(path, t, data);
    return;
  }
  if (t.exists) {
    // Keep the replaced file's permission bits.
    fs::permissions(tmp, fs::status(t.path, ec).permissions(), fs::perm_options::replace, ec);
  }
  fs::rename(tmp, t.path, ec);
  if (ec) {
    cleanup();
    throw InputError(path + ": cannot write: " + ec.message());
  }
}

void write_file_atomic(const std::string& path, const std::string& content) {
  // In place the content is written directly (no temporary copy of data already in memory).
  if (const Target t = find_target(path); t.in_place) return write_data_in_place(path, t, content);
  write_via_temporary(path, [&](const std::string& tmp) { write_new_file(path, tmp, content); });
}

}  // namespace skin::util::io
