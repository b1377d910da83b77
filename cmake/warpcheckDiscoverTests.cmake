# warpcheck_discover_tests(<target>
#                          [EXTRA_ARGS <arg>...]
#                          [TEST_PREFIX <prefix>]
#                          [LABELS <label>...]
#                          [PROPERTIES <name> <value>...])
#
# Registers one ctest test per (case, check) of <target>, a program built on
# warpcheck::main, labelled with the check's name: `ctest -L chi2` runs the
# chi-square tests, `ctest --output-junit FILE` reports each case apart.
#
# The jobs are listed when ctest reads the tests (the program's --list-jobs,
# with EXTRA_ARGS, default --all), so a case added to the program appears
# without reconfiguring. Test k of the N jobs runs `<target> EXTRA_ARGS
# --shard k/N`: the one job, judged at the Šidák level of all N together, with
# the figures of the whole run. Tests are named <prefix><check>/<case>, the
# prefix being "<target>/" unless TEST_PREFIX says otherwise, and the case
# written so that the name, given to `ctest -R`, selects its test: '[' and ']'
# as '{' and '}', and each of ( ) * + ? | ^ $ \ ; as '_'
# (power[n=4] is <prefix>chi2/power{n=4}); two cases that read alike then
# carry 8 hex digits of a hash each (power{n=4}~1f7313ff). LABELS are added
# to every test beside the check's name; PROPERTIES are set on every test
# (e.g. TIMEOUT 600).
#
# As with the GoogleTest adapter, WARPCHECK_SEED, WARPCHECK_SAMPLES,
# WARPCHECK_ALPHA, WARPCHECK_TIME_BUDGET and WARPCHECK_MEMORY_LIMIT in ctest's
# environment replace the seed, sample count, alpha, time budget and memory
# limit of EXTRA_ARGS (`WARPCHECK_SAMPLES=10M ctest`), and an invalid value
# fails every test with the variable's name and the reason. A failing test
# writes its HTML report to WARPCHECK_EVIDENCE_DIR (default warpcheck-evidence
# in the target's build folder), in ctest/<prefix>/ (the GoogleTest adapter
# writes in gtest/), as <case>__<check>.html (a name over 255 bytes shortened,
# with a hash of the case), and names it.
function(warpcheck_discover_tests target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "TEST_PREFIX" "EXTRA_ARGS;LABELS;PROPERTIES")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "warpcheck_discover_tests: unknown arguments: ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT TARGET ${target})
    message(FATAL_ERROR "warpcheck_discover_tests: '${target}' is not a target")
  endif()
  if(NOT DEFINED arg_TEST_PREFIX)
    set(arg_TEST_PREFIX "${target}/")
  endif()
  if(NOT arg_EXTRA_ARGS)
    set(arg_EXTRA_ARGS --all)
  endif()
  set(settings "${CMAKE_CURRENT_BINARY_DIR}/${target}_warpcheck_tests.cmake")
  # Bracket arguments keep every character; lists travel as CMake lists.
  file(GENERATE OUTPUT "${settings}" CONTENT
"set(warpcheck_program [==[$<TARGET_FILE:${target}>]==])
set(warpcheck_args [==[${arg_EXTRA_ARGS}]==])
set(warpcheck_prefix [==[${arg_TEST_PREFIX}]==])
set(warpcheck_labels [==[${arg_LABELS}]==])
set(warpcheck_properties [==[${arg_PROPERTIES}]==])
set(warpcheck_directory [==[${CMAKE_CURRENT_BINARY_DIR}]==])
include([==[${_WARPCHECK_ADD_JOB_TESTS}]==])
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${settings}")
endfunction()

# The script that ctest runs for each such program (it reads the variables above).
set(_WARPCHECK_ADD_JOB_TESTS "${CMAKE_CURRENT_LIST_DIR}/warpcheckAddJobTests.cmake")
