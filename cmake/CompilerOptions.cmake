# Warnings and sanitizers for every warpcheck target, through one interface target.
add_library(warpcheck_options INTERFACE)
target_compile_options(warpcheck_options INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
if(WARPCHECK_WERROR)
  target_compile_options(warpcheck_options INTERFACE -Werror)
endif()
if(WARPCHECK_SANITIZE)
  # Instrumented code defeats GCC 12's flow analysis: -Wmaybe-uninitialized then
  # fires inside libstdc++ (std::regex, std::function) where nothing is wrong.
  # The uninstrumented build keeps the warning, with -Werror.
  target_compile_options(warpcheck_options INTERFACE
    -fsanitize=${WARPCHECK_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all
    -Wno-maybe-uninitialized)
  target_link_options(warpcheck_options INTERFACE -fsanitize=${WARPCHECK_SANITIZE})
endif()
