#include "skin/util/input_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "skin/util/error.hpp"

namespace skin::util::io {

namespace fs = std::filesystem;

namespace {
[[noreturn]] void fail(const std::string& path, const std::string& what, const std::string& problem) {
  throw InputError(what + " = '" + path + "': " + problem);
}

std::string size_text(std::uintmax_t bytes) {
  return format_number(static_cast<double>(bytes) / (1 << 20)) + " MiB";
}
}  // namespace

namespace {
void check(const std::string& path, const std::string& what, std::uintmax_t max_bytes, bool streams) {
  if (path.empty()) fail(path, what, "an empty file name was given");
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail(path, what, "file not found");
  if (fs::is_directory(st)) fail(path, what, "is a directory, not a file");
  if (fs::is_regular_file(st)) {
    const std::uintmax_t size = fs::file_size(path, ec);
    if (!ec && size > max_bytes)
      fail(path, what, "the file is " + size_text(size) + ", more than the " + size_text(max_bytes) +
                           " this reader takes");
  } else if (!streams || (!fs::is_fifo(st) && !fs::is_character_file(st))) {
    fail(path, what, "is not a regular file");
  }
  if (::access(path.c_str(), R_OK) != 0) fail(path, what, std::string("cannot read: ") + std::strerror(errno));
}
}  // namespace

void check_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  check(path, what, max_bytes, false);
}

std::string read_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  check(path, what, max_bytes, true);
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(path, what, std::string("cannot open: ") + std::strerror(errno));
  std::string data;
  char buffer[1 << 16];
  for (;;) {
    // At most max_bytes + 1 bytes in all: one more than allowed proves a stream too long.
    const std::uintmax_t remaining = max_bytes - data.size();  // (data.size() <= max_bytes here)
    const std::size_t want = remaining >= sizeof buffer ? sizeof buffer : static_cast<std::size_t>(remaining) + 1;
    const ssize_t n = ::read(fd, buffer, want);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      fail(path, what, std::string("read error: ") + std::strerror(err));
    }
    if (n == 0) break;
    // Text never holds a NUL byte: a binary file, or /dev/zero, which never ends.
    if (const void* nul = std::memchr(buffer, '\0', static_cast<std::size_t>(n))) {
      ::close(fd);
      const auto at = data.size() + static_cast<std::size_t>(static_cast<const char*>(nul) - buffer);
      fail(path, what, "not a text file (a NUL byte at byte " + std::to_string(at) + ")");
    }
    data.append(buffer, static_cast<std::size_t>(n));
    if (data.size() > max_bytes) {  // a stream (FIFO) that does not end
      ::close(fd);
      fail(path, what, "more than the " + size_text(max_bytes) + " this reader takes");
    }
  }
  ::close(fd);
  return data;
}

}  // namespace skin::util::io
