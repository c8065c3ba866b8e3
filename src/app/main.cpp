// The `skin` command: thin front end over the Spectral Skin libraries. User errors (bad
// parameters, files) are reported once here, as one line, with exit code 2.
#include <iostream>

#include "common.hpp"
#include "skin/util/error.hpp"

#if defined(__SANITIZE_ADDRESS__)
// LeakSanitizer builds (SKIN_SANITIZE): fontconfig, used by Cairo to draw plot text, keeps a
// process-lifetime cache that it never frees; that is not a leak of ours.
extern "C" const char* __lsan_default_suppressions();
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig\n"; }
#endif

int main(int argc, char** argv) {
  using namespace skin::cli;
  CLI::App app{
      "Spectral Skin: physically based skin appearance from four biophysical parameters\n"
      "(after Donner & Jensen 2006). Units: lengths in mm, coefficients in 1/mm, wavelengths "
      "in nm."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("skin 0.1.0"));
  register_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "skin: error: " << e.what() << " (run with --help for the options)\n";
    return 2;
  } catch (const skin::InputError& e) {
    std::cerr << "skin: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "skin: error: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
