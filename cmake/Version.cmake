# warpcheck/version.h, generated into the build tree from project(VERSION) and
# the compiler CMake found. The results library puts the folder on the include
# path; Install.cmake installs the header.
set(WARPCHECK_GENERATED_INCLUDE_DIR "${PROJECT_BINARY_DIR}/include")
configure_file(cmake/version.h.in "${WARPCHECK_GENERATED_INCLUDE_DIR}/warpcheck/version.h" @ONLY)
