// The `skin` command: thin front end over the Spectral Skin libraries. User errors (bad
// parameters, files) are reported once here, as one line, with exit code 2. SIGINT and SIGTERM
// cancel the running computation (skin/util/cancel.hpp): the command stops at the libraries'
// next poll, writes nothing and exits with 128 + the signal's number; a second signal ends the
// process at once (its default action).
#include <csignal>
#include <iostream>
#include <sstream>

#include "common.hpp"
#include "skin/util/allocator.hpp"
#include "skin/util/atomic_file.hpp"
#include "skin/util/cancel.hpp"
#include "skin/util/error.hpp"

namespace {
volatile std::sig_atomic_t received_signal = 0;

extern "C" void on_signal(int sig) {
  received_signal = sig;
  skin::util::cancel::request();
}

void install_signal_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART | SA_RESETHAND;  // the next signal takes its default action
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}
}  // namespace

#if defined(__SANITIZE_ADDRESS__)  // GCC
#define SKIN_ASAN 1
#elif defined(__has_feature)  // clang
#if __has_feature(address_sanitizer)
#define SKIN_ASAN 1
#endif
#endif
#if defined(SKIN_ASAN)
// LeakSanitizer builds (SKIN_SANITIZE): fontconfig, used by Cairo to draw plot text, keeps a
// process-lifetime cache that it never frees; that is not a leak of ours.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }
#endif

// Standard output is checked once more at the end: what a command wrote there and could not
// (a full disk, /dev/full) is an error, exit 2, never a silent success.
int main(int argc, char** argv) {
  using namespace skin::cli;
  skin::util::keep_matrix_memory();
  CLI::App app{
      "Spectral Skin: physically based skin appearance from four biophysical parameters\n"
      "(after Donner & Jensen 2006). Units: lengths in mm, coefficients in 1/mm, wavelengths "
      "in nm."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("skin 0.1.0"));
  register_commands(app);
  install_signal_handlers();
  int code = 0;
  try {
    // --help and --version: the text goes out through the one checked writer.
    std::ostringstream text;
    try {
      app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
      code = app.exit(e, text);
    } catch (const CLI::CallForAllHelp& e) {
      code = app.exit(e, text);
    } catch (const CLI::CallForVersion& e) {
      code = app.exit(e, text);
    }
    skin::util::io::write_stdout(text.str());  // (flushes what the command wrote first)
  } catch (const CLI::ParseError& e) {
    std::cerr << "skin: error: " << e.what() << " (run with --help for the options)\n";
    return 2;
  } catch (const skin::util::Cancelled&) {
    const int sig = received_signal;
    std::cerr << "skin: interrupted by " << (sig == SIGTERM ? "SIGTERM" : "SIGINT")
              << ": stopped, no output written\n";
    return 128 + (sig ? sig : SIGINT);
  } catch (const skin::util::InputError& e) {
    std::cerr << "skin: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "skin: error: " << e.what() << '\n';
    return 1;
  }
  return code;
}
