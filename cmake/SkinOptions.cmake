# Interface targets carrying warnings and sanitizer flags; every library links them.
add_library(skin_warnings INTERFACE)
target_compile_options(skin_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
  -Wno-sign-conversion)
add_library(skin::warnings ALIAS skin_warnings)

add_library(skin_sanitize INTERFACE)
if(SKIN_SANITIZE)
  # ASan + UBSan; no recovery so that any report fails the test that triggered it.
  target_compile_options(skin_sanitize INTERFACE -fsanitize=address,undefined
    -fno-sanitize-recover=all -fno-omit-frame-pointer -g)
  target_link_options(skin_sanitize INTERFACE -fsanitize=address,undefined)
endif()
add_library(skin::sanitize ALIAS skin_sanitize)
# No -ffast-math anywhere: tests compare the physics to reference values.
