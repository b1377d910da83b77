# Run by ctest (TEST_INCLUDE_FILES) for a program given to
# warpcheck_discover_tests: one test per line of its --list-jobs ("<check>\t<case>").
if(NOT EXISTS "${warpcheck_program}")
  # Not built yet: one test that says so, rather than none.
  add_test("${warpcheck_prefix}NOT_BUILT" "${warpcheck_program}")
  return()
endif()
execute_process(COMMAND "${warpcheck_program}" --list-jobs ${warpcheck_args}
  OUTPUT_VARIABLE jobs ERROR_VARIABLE problem RESULT_VARIABLE status
  WORKING_DIRECTORY "${warpcheck_directory}" TIMEOUT 120)
if(NOT status EQUAL 0)
  # The listing failed (bad EXTRA_ARGS, a registration that throws): one test
  # that runs it again, and fails with its message.
  add_test("${warpcheck_prefix}LIST_JOBS" "${warpcheck_program}" --list-jobs ${warpcheck_args})
  return()
endif()
string(REGEX REPLACE "\n$" "" jobs "${jobs}")
string(REPLACE ";" "\\;" jobs "${jobs}")
string(REPLACE "\n" ";" jobs "${jobs}")
list(LENGTH jobs count)
set(index 0)
foreach(job IN LISTS jobs)
  math(EXPR index "${index} + 1")
  string(FIND "${job}" "\t" tab)
  string(SUBSTRING "${job}" 0 ${tab} check)
  math(EXPR start "${tab} + 1")
  string(SUBSTRING "${job}" ${start} -1 case)
  set(name "${warpcheck_prefix}${check}/${case}")
  add_test("${name}" "${warpcheck_program}" ${warpcheck_args} --shard ${index}/${count} --color never)
  set_tests_properties("${name}" PROPERTIES LABELS "${check};${warpcheck_labels}"
    WORKING_DIRECTORY "${warpcheck_directory}" ${warpcheck_properties})
endforeach()
