#pragma once
// Writing output files without ever leaving a half-written one or damaging what the path names:
// - a regular file (or a new name): the data go to a temporary file beside it, renamed over it
//   only once complete (the replaced file's permission bits are kept);
// - a symbolic link: the same, for the file the link points to (the link stays a link);
// - a FIFO, character or block device (/dev/null, /dev/stdout, a pipe): written in place, never
//   replaced;
// - "-": standard output (write_stdout).
// On failure (a full disk, an unwritable directory, an exception of the writer) the temporary
// file is removed and nothing that existed is touched; an InputError names the file.
#include <functional>
#include <string>
#include <string_view>

namespace skin::util::io {

// Writes `content` to `path` as above. Throws InputError naming the file on failure.
void write_file_atomic(const std::string& path, const std::string& content);

// Calls write(tmp_path) to produce the file under a temporary name (beside the target, with the
// target's extension, since some writers choose the format from it), then puts it in place as
// above. For libraries that insist on writing to a path themselves (PNG, EXR, Cairo).
void write_via_temporary(const std::string& path, const std::function<void(const std::string&)>& write);

// Standard output, the one way every command's output goes there: writes `data` after what
// std::cout and C's stdout still buffer (so the order is kept), and throws InputError
// "output = '-': write failed: <reason>" when it cannot (a full disk, /dev/full, a closed pipe
// with SIGPIPE ignored).
void write_stdout(std::string_view data);
// Flushes std::cout and C's stdout; the same InputError when that fails or when any earlier write
// to them failed. The `skin` command calls it before it exits, so that no output is lost silently.
void flush_stdout();

// Lower-case extension of a path without the dot ("png"), or "" if none.
std::string extension(const std::string& path);

}  // namespace skin::util::io
