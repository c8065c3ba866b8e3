#pragma once
// Runs `skin` as a child process in a directory, with stdout and stderr captured in files,
// optional resource limits, and a signal sent after a delay (or once stderr shows a given text);
// reports how it ended.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
#include "skin_test_paths.hpp"

namespace skin_test {
namespace fs = std::filesystem;

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Splits "a b c" at spaces (the tests' arguments have no quoted spaces).
inline std::vector<std::string> split_args(const std::string& args) {
  std::vector<std::string> out;
  std::istringstream in(args);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

struct Exit {
  int code = -1;            // exit status, or -1 if killed by a signal
  int signal = 0;           // the signal that killed it, if any
  double seconds_after_signal = -1;  // from the signal sent to the exit
  std::string out, err;
};

struct Spawn {
  Spawn(fs::path d = {}, std::string a = {}) : dir(std::move(d)), args(std::move(a)) {}
  fs::path dir;                 // working directory (its stdout and stderr files go beside it)
  std::string args;             // arguments of `skin`
  long file_size_limit = -1;    // RLIMIT_FSIZE in bytes (-1: none); SIGXFSZ is ignored
  int send_signal = 0;          // sent after `delay` (0: none)
  double delay = 0;             // seconds
  std::string signal_when;      // if set, the signal waits (after `delay`) until stderr holds this text
  double timeout = 120;         // killed (SIGKILL) after this many seconds; a failure
  std::vector<std::string> prefix;  // run through another program first (taskset ...)
};

inline Exit run_skin(const Spawn& s) {
  const fs::path out = s.dir.parent_path() / (s.dir.filename().string() + ".stdout");
  const fs::path err = s.dir.parent_path() / (s.dir.filename().string() + ".stderr");
  std::vector<std::string> argv = s.prefix;
  argv.push_back(SKIN_BINARY);
  for (auto& a : split_args(s.args)) argv.push_back(a);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(s.dir.c_str()) != 0) ::_exit(127);
    const int fo = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fe = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fi = ::open("/dev/null", O_RDONLY);
    ::dup2(fo, 1), ::dup2(fe, 2), ::dup2(fi, 0);
    if (s.file_size_limit >= 0) {
      ::signal(SIGXFSZ, SIG_IGN);  // the write then fails with EFBIG, as on a full disk
      const rlimit r{static_cast<rlim_t>(s.file_size_limit), static_cast<rlim_t>(s.file_size_limit)};
      ::setrlimit(RLIMIT_FSIZE, &r);
    }
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    ::execvp(cargv[0], cargv.data());
    ::_exit(127);
  }
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  Clock::time_point signalled{};
  bool sent = false;
  int status = 0;
  for (;;) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    const double t = std::chrono::duration<double>(Clock::now() - start).count();
    if (s.send_signal && !sent && t >= s.delay &&
        (s.signal_when.empty() || read_text(err).find(s.signal_when) != std::string::npos)) {
      ::kill(pid, s.send_signal);
      signalled = Clock::now();
      sent = true;
    }
    if (t > s.timeout) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      ADD_FAILURE() << "skin " << s.args << ": still running after " << s.timeout << " s";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  Exit e;
  if (WIFEXITED(status)) e.code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) e.signal = WTERMSIG(status);
  if (sent) e.seconds_after_signal = std::chrono::duration<double>(Clock::now() - signalled).count();
  e.out = read_text(out);
  e.err = read_text(err);
  fs::remove(out);
  fs::remove(err);
  return e;
}

// A fresh directory per test, removed afterwards.
class InDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("skin_faults_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  Exit run(const std::string& args) { return run_skin({dir_, args}); }
  // Names in the directory (recursively), sorted: shows any temporary file left behind.
  std::vector<std::string> listing(const fs::path& under = {}) const {
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(under.empty() ? dir_ : under))
      names.push_back(fs::relative(e.path(), under.empty() ? dir_ : under).string());
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

// One line on stderr (ends with a newline, none before).
inline bool one_line(const std::string& err) {
  return !err.empty() && err.back() == '\n' && err.find('\n') == err.size() - 1;
}

}  // namespace skin_test
