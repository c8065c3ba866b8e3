// Registers the subcommands of optional parts (renderer, Monte Carlo, fitting). Each part adds a
// call here when it is built; see src/app/CMakeLists.txt.
#include "common.hpp"

namespace skin::cli {
#ifdef SKIN_HAVE_MC
void register_mc(CLI::App& app);
#endif
#ifdef SKIN_HAVE_RENDER
void register_render(CLI::App& app);
#endif
#ifdef SKIN_HAVE_FIT
void register_fit(CLI::App& app);
#endif

void register_extra_commands([[maybe_unused]] CLI::App& app) {
#ifdef SKIN_HAVE_MC
  register_mc(app);
#endif
#ifdef SKIN_HAVE_RENDER
  register_render(app);
#endif
#ifdef SKIN_HAVE_FIT
  register_fit(app);
#endif
}

}  // namespace skin::cli
