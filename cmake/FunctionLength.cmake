# Run as `cmake -DSOURCE_DIR=... -DBUILD_DIR=... -P FunctionLength.cmake` (the
# ctest function_length): fails, listing them, when a production function
# (sampling/, chi2/, validate/, reports/; not tests/) is longer than 80 lines,
# by clang-tidy's readability-function-size over every production .cpp in the
# build's compile_commands.json (CMAKE_EXPORT_COMPILE_COMMANDS, on by default
# in the top CMakeLists.txt). Functions in production headers count once, through the .cpp files
# that include them. Exits 77 (the test's SKIP_RETURN_CODE) without clang-tidy.
cmake_minimum_required(VERSION 3.25)
set(line_threshold 80)

find_program(CLANG_TIDY NAMES clang-tidy clang-tidy-18 clang-tidy-17 clang-tidy-16 clang-tidy-15 clang-tidy-14)
if(NOT CLANG_TIDY)
  message("clang-tidy not found: function_length skipped")
  cmake_language(EXIT 77)
endif()
set(database "${BUILD_DIR}/compile_commands.json")
if(NOT EXISTS "${database}")
  # The top CMakeLists.txt turns the export on; only a generator without it
  # (Visual Studio, Xcode) or an explicit -DCMAKE_EXPORT_COMPILE_COMMANDS=OFF gets here.
  message("${database} missing (a generator that does not write it, or CMAKE_EXPORT_COMPILE_COMMANDS=OFF): function_length skipped")
  cmake_language(EXIT 77)
endif()

# The production translation units named in the compilation database.
file(READ "${database}" json)
string(JSON count LENGTH "${json}")
math(EXPR last "${count} - 1")
set(sources "")
foreach(i RANGE ${last})
  string(JSON file GET "${json}" ${i} file)
  file(RELATIVE_PATH rel "${SOURCE_DIR}" "${file}")
  if(rel MATCHES "^(sampling|chi2|validate|reports)/.*\\.cpp$")
    list(APPEND sources "${file}")
  endif()
endforeach()
list(REMOVE_DUPLICATES sources)
list(LENGTH sources n)
if(n EQUAL 0)
  message(FATAL_ERROR "no production .cpp in ${database}")
endif()

# Only this one check, so that the run is fast and the result is about length only.
set(config "{Checks: '-*,readability-function-size', CheckOptions: [{key: readability-function-size.LineThreshold, value: ${line_threshold}}]}")
# One clang-tidy over all files: ~90 s of CPU (175 s on the shared 2-core
# machine); run-clang-tidy -j 2 was no faster there, so it stays this simple.
execute_process(
  COMMAND "${CLANG_TIDY}" -p "${BUILD_DIR}" --quiet "--config=${config}"
          "--header-filter=^${SOURCE_DIR}/(sampling|chi2|validate|reports)/"
          --extra-arg=-Wno-unknown-warning-option ${sources}
  OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)

# "file:line:col: warning: function 'f' exceeds ..." followed by the note
# "file:line:col: note: N lines including whitespace and comments (threshold 80)".
string(REPLACE "\n" ";" lines "${out}")
set(offenders "")
set(pending "")
foreach(line IN LISTS lines)
  if(line MATCHES "^([^:]+):([0-9]+):[0-9]+: warning: function '([^']+)' exceeds recommended size")
    file(RELATIVE_PATH rel "${SOURCE_DIR}" "${CMAKE_MATCH_1}")
    set(pending "${rel}:${CMAKE_MATCH_2}: ${CMAKE_MATCH_3}")
  elseif(pending AND line MATCHES "note: ([0-9]+) lines including")
    list(APPEND offenders "${pending} (${CMAKE_MATCH_1} lines)")
    set(pending "")
  endif()
endforeach()
list(REMOVE_DUPLICATES offenders)
list(SORT offenders)
if(offenders)
  list(JOIN offenders "\n  " listing)
  message(FATAL_ERROR "Production functions longer than ${line_threshold} lines:\n  ${listing}")
endif()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "clang-tidy failed (exit ${rc}) on ${n} files:\n${err}\n${out}")
endif()
message("function_length: ${n} production files, no function over ${line_threshold} lines")
