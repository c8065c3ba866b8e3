#pragma once
// Shared pieces of the libFuzzer harnesses (fuzz/README.md).
// A harness feeds the fuzzer's bytes to the project's own reading code. The contract it checks:
// any input either parses or throws skin::util::InputError (one line for the user, exit 2 in the CLI);
// every other exception, a crash, a hang, an out-of-memory or a sanitizer report is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "skin/util/error.hpp"

namespace skin::fuzz {

// The fuzzer's bytes as text.
inline std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// A finding: prints the message and aborts, so that libFuzzer saves the input.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// Runs `parse`; an InputError is the expected answer to a bad input (its message must be one
// non-empty line, free of control characters), anything else thrown is a finding. Returns
// whether `parse` succeeded.
template <class F>
bool accepts(F&& parse) {
  try {
    parse();
    return true;
  } catch (const util::InputError& e) {
    const std::string_view m = e.what();
    bool control = false;
    for (const char c : m) control = control || static_cast<unsigned char>(c) < 0x20;
    if (m.empty() || control) finding("InputError is not one line: '" + std::string(m) + "'");
    return false;
  } catch (const std::exception& e) {
    finding(std::string("exception other than InputError: ") + e.what());
  } catch (...) {
    finding("unknown exception");
  }
}

// A file holding the fuzzer's bytes, for readers that take a path (PNG, EXR, OBJ, glTF, JSON
// files). One per process and extension, rewritten for each input, in the temporary directory.
class InputFile {
 public:
  explicit InputFile(const std::string& extension) {
    path_ = (std::filesystem::temp_directory_path() /
             ("skin-fuzz-" + std::to_string(::getpid()) + "." + extension))
                .string();
  }
  ~InputFile() { std::remove(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  const std::string& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) finding("cannot write the input file " + path_);
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace skin::fuzz
