# Run by ctest (TEST_INCLUDE_FILES) for a program given to
# warpcheck_discover_tests: one test per line of its --list-jobs ("<check>\t<case>").
if(NOT EXISTS "${warpcheck_program}")
  # Not built yet: one test that says so, rather than none.
  add_test("${warpcheck_prefix}NOT_BUILT" "${warpcheck_program}")
  return()
endif()
# The listing does not read WARPCHECK_SEED, _SAMPLES or _ALPHA (the jobs do not
# depend on them): with an invalid value, every test is still there, and fails
# with the variable's name and the reason.
execute_process(COMMAND "${warpcheck_program}" --list-jobs ${warpcheck_args}
  OUTPUT_VARIABLE jobs ERROR_VARIABLE problem RESULT_VARIABLE status
  WORKING_DIRECTORY "${warpcheck_directory}" TIMEOUT 120)
if(NOT status EQUAL 0)
  # The listing failed (bad EXTRA_ARGS, a registration that throws): one test
  # that runs it again, and fails with its message.
  add_test("${warpcheck_prefix}LIST_JOBS" "${warpcheck_program}" --list-jobs ${warpcheck_args})
  return()
endif()
# Where a failing test writes its HTML report: WARPCHECK_EVIDENCE_DIR as ctest
# sees it (relative to the tests' working directory), else warpcheck-evidence
# there, as for the GoogleTest adapter.
if(NOT "$ENV{WARPCHECK_EVIDENCE_DIR}" STREQUAL "")
  get_filename_component(evidence "$ENV{WARPCHECK_EVIDENCE_DIR}" ABSOLUTE BASE_DIR "${warpcheck_directory}")
else()
  set(evidence "${warpcheck_directory}/warpcheck-evidence")
endif()
file(MAKE_DIRECTORY "${evidence}")
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
  # The evidence file: <case>__<check> with letters and digits kept, the rest
  # '_' (as the GoogleTest adapter names it), and the job's number after a
  # name that an earlier job already has.
  string(REGEX REPLACE "[^A-Za-z0-9]" "_" file_case "${case}")
  string(REGEX REPLACE "_+$" "" file_case "${file_case}")
  set(file "${file_case}__${check}")
  if(DEFINED warpcheck_file_${file})
    set(file "${file}_${index}")
  endif()
  set(warpcheck_file_${file} 1)
  add_test("${name}" "${warpcheck_program}" ${warpcheck_args} --shard ${index}/${count} --color never
    --progress none --settings-from-environment --report-on-failure "${evidence}/${file}.html")
  set_tests_properties("${name}" PROPERTIES LABELS "${check};${warpcheck_labels}"
    WORKING_DIRECTORY "${warpcheck_directory}" ${warpcheck_properties})
endforeach()
