# Warnings and sanitizers for every warpcheck target, through one interface target.
# The build is kept warning-free with both GCC and Clang (presets test and clang).
add_library(warpcheck_options INTERFACE)
target_compile_options(warpcheck_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
# Floating point as written, on every target: no multiply-add contraction, so
# the vectorised forms of the warps (sampling/lanes.h), compiled for AVX-512
# inside the same program, give the same bits as their scalar forms.
target_compile_options(warpcheck_options INTERFACE -ffp-contract=off)
if(WARPCHECK_WERROR)
  target_compile_options(warpcheck_options INTERFACE -Werror)
endif()
if(WARPCHECK_SANITIZE)
  target_compile_options(warpcheck_options INTERFACE
    -fsanitize=${WARPCHECK_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(warpcheck_options INTERFACE -fsanitize=${WARPCHECK_SANITIZE})
  # Instrumented code defeats GCC 12's flow analysis: -Wmaybe-uninitialized then
  # fires inside libstdc++ (std::regex, std::function) where nothing is wrong.
  # The uninstrumented build keeps the warning, with -Werror. Clang has no such
  # warning (and would warn about the unknown option).
  target_compile_options(warpcheck_options INTERFACE
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
endif()
