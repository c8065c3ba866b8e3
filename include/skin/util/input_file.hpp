#pragma once
// Reading input files with one clear line on every failure: the file named, and what is wrong
// (missing, a directory or other non-regular file, unreadable, larger than the reader takes).
#include <cstdint>
#include <string>

namespace skin::util::io {

// Text inputs (CSV tables, JSON) are read whole into memory; larger ones are refused before
// reading (measured spectra, scenes and parameter files are kilobytes to megabytes).
inline constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{256} << 20;

// Throws InputError "<what> = '<path>': <problem>" unless `path` names a readable regular file
// of at most `max_bytes` bytes. For readers that take a path (images, meshes): a FIFO or a
// device such as /dev/zero, which may never end, is refused.
void check_input_file(const std::string& path, const std::string& what,
                      std::uintmax_t max_bytes = UINTMAX_MAX);

// The whole content of a text file, checked as above, at most `max_bytes` bytes; a FIFO or
// character device (/dev/stdin, a process substitution) is read as a stream, never more than
// max_bytes + 1 bytes. A NUL byte, which no text holds (a binary file, /dev/zero), is refused
// as soon as it is read.
std::string read_file(const std::string& path, const std::string& what,
                      std::uintmax_t max_bytes = kMaxTextFileBytes);

}  // namespace skin::util::io
