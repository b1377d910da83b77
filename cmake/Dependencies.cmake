# Every dependency comes from a Debian 12 package. A missing one stops the
# configuration with the name of the package that provides it.
function(warpcheck_require package debian_package)
  find_package(${package} ${ARGN} QUIET)
  if(NOT ${package}_FOUND)
    message(FATAL_ERROR
      "warpcheck needs ${package}, which was not found.\n"
      "On Debian 12 install it with:  apt-get install ${debian_package}\n"
      "(or run .ci/install-deps, which installs everything warpcheck needs)")
  endif()
endfunction()

warpcheck_require(Boost libboost-math-dev 1.74)   # Boost.Math is header-only
warpcheck_require(Eigen3 libeigen3-dev 3.4 NO_MODULE)
warpcheck_require(CLI11 libcli11-dev)
warpcheck_require(fmt libfmt-dev)
warpcheck_require(nlohmann_json nlohmann-json3-dev)
warpcheck_require(Threads libc6-dev)
warpcheck_require(ZLIB zlib1g-dev)                # the HTML report's images and packed evidence
if(WARPCHECK_BUILD_TESTS)
  warpcheck_require(GTest "libgtest-dev libgmock-dev")
  warpcheck_require(benchmark libbenchmark-dev)
endif()
