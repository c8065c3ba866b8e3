# Interface targets carrying warnings and sanitizer flags; every library links them.
add_library(skin_warnings INTERFACE)
target_compile_options(skin_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
  -Wno-sign-conversion)
add_library(skin::warnings ALIAS skin_warnings)

add_library(skin_sanitize INTERFACE)
if(SKIN_SANITIZE OR SKIN_FUZZ)
  # ASan + UBSan; no recovery so that any report fails the test that triggered it. Line tables
  # are all the reports need (file:line in stack traces) and build faster than full debug info.
  # SKIN_FUZZ adds libFuzzer's coverage instrumentation (the harnesses in fuzz/ link
  # -fsanitize=fuzzer; tests link the sanitizers' weak defaults of its callbacks).
  set(skin_sanitizers address,undefined)
  if(SKIN_FUZZ)
    set(skin_sanitizers fuzzer-no-link,${skin_sanitizers})
  endif()
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    set(skin_debug_info -gline-tables-only)
  else()
    set(skin_debug_info -g1)
  endif()
  target_compile_options(skin_sanitize INTERFACE -fsanitize=${skin_sanitizers}
    -fno-sanitize-recover=all -fno-omit-frame-pointer ${skin_debug_info})
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    # UBSan's checks skip Eigen's own code (the file says why). ccache 4.7 neither hashes the
    # list's content (so its hash is part of the command line) nor rewrites the option's path
    # under its base directory: with Ninja, which compiles from the build directory, the path is
    # relative to it, so that a fresh clone elsewhere (CI) hits the same cache entries.
    set(skin_ubsan_ignorelist ${CMAKE_CURRENT_LIST_DIR}/ubsan-ignorelist.txt)
    file(SHA1 ${skin_ubsan_ignorelist} skin_ubsan_ignorelist_sha1)
    set(skin_ubsan_ignorelist_arg ${skin_ubsan_ignorelist})
    if(CMAKE_GENERATOR MATCHES "Ninja")
      file(RELATIVE_PATH skin_ubsan_ignorelist_arg ${CMAKE_BINARY_DIR} ${skin_ubsan_ignorelist})
    endif()
    # (The project's own compilations only: the installed package's consumers compile their own
    # code, from their own build directories.)
    target_compile_options(skin_sanitize INTERFACE
      $<BUILD_INTERFACE:-fsanitize-ignorelist=${skin_ubsan_ignorelist_arg}>)
    target_compile_definitions(skin_sanitize INTERFACE
      $<BUILD_INTERFACE:SKIN_UBSAN_IGNORELIST=${skin_ubsan_ignorelist_sha1}>)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${skin_ubsan_ignorelist})
  endif()
  target_link_options(skin_sanitize INTERFACE -fsanitize=address,undefined)
endif()
add_library(skin::sanitize ALIAS skin_sanitize)
# No -ffast-math anywhere: tests compare the physics to reference values.
