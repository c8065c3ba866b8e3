#pragma once
// Writing output files without ever leaving a half-written one: the data go to a temporary file
// next to the target, which is renamed over it only once it is complete. On failure the target is
// untouched (a file the user already had stays as it was) and the temporary file is removed.
#include <functional>
#include <string>

namespace skin::io {

// Writes `content` to `path` atomically. Throws InputError naming the file on failure.
void write_file_atomic(const std::string& path, const std::string& content);

// Calls write(tmp_path) to produce the file under a temporary name, then renames it to `path`.
// For libraries that insist on writing to a path themselves (PNG, EXR, Cairo).
void write_via_temporary(const std::string& path, const std::function<void(const std::string&)>& write);

// Lower-case extension of a path without the dot ("png"), or "" if none.
std::string extension(const std::string& path);

}  // namespace skin::io
