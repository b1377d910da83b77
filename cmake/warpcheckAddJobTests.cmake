# Run by ctest (TEST_INCLUDE_FILES) for a program given to
# warpcheck_discover_tests: one test per line of its --list-jobs ("<check>\t<case>").
# In a function: its variables stay its own, apart from those of the other
# programs' listings that ctest reads in the same folder.
function(_warpcheck_add_job_tests)
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
  # there, as for the GoogleTest adapter; in a folder of its own, ctest/<prefix>,
  # so that the GoogleTest adapter (gtest/<suite>) and another program's tests
  # never write the same file.
  if(NOT "$ENV{WARPCHECK_EVIDENCE_DIR}" STREQUAL "")
    get_filename_component(evidence "$ENV{WARPCHECK_EVIDENCE_DIR}" ABSOLUTE BASE_DIR "${warpcheck_directory}")
  else()
    set(evidence "${warpcheck_directory}/warpcheck-evidence")
  endif()
  string(REGEX REPLACE "[^A-Za-z0-9]" "_" prefix_folder "${warpcheck_prefix}")
  string(REGEX REPLACE "^_+|_+$" "" prefix_folder "${prefix_folder}")
  set(evidence "${evidence}/ctest")
  if(NOT prefix_folder STREQUAL "")
    set(evidence "${evidence}/${prefix_folder}")
  endif()
  file(MAKE_DIRECTORY "${evidence}")

  # The lines as a CMake list. A list does not split at a ';' inside [...], and
  # a case name may hold an unbalanced '[' (or an escape sequence, printed as
  # \x1b[...): the brackets are set aside as bytes the listing never holds
  # (--list-jobs writes control bytes as \xNN) and put back in each line.
  string(ASCII 1 open_bracket)
  string(ASCII 2 close_bracket)
  string(REGEX REPLACE "\n$" "" jobs "${jobs}")
  string(REPLACE "[" "${open_bracket}" jobs "${jobs}")
  string(REPLACE "]" "${close_bracket}" jobs "${jobs}")
  string(REPLACE ";" "\\;" jobs "${jobs}")
  string(REPLACE "\n" ";" jobs "${jobs}")
  list(LENGTH jobs count)
  if(count EQUAL 0)
    return()
  endif()
  set(index 0)
  foreach(job IN LISTS jobs)
    math(EXPR index "${index} + 1")
    string(REPLACE "${open_bracket}" "[" job "${job}")
    string(REPLACE "${close_bracket}" "]" job "${job}")
    string(FIND "${job}" "\t" tab)
    string(SUBSTRING "${job}" 0 ${tab} check)
    math(EXPR start "${tab} + 1")
    string(SUBSTRING "${job}" ${start} -1 case)

    # The test's name: <prefix><check>/<case>, with the characters that a ctest
    # -R regular expression reads specially made plain, so that a name copied
    # from `ctest -N` selects its test: '[' and ']' become '{' and '}', and each
    # of ( ) * + ? | ^ $ \ becomes '_' (';' too: ctest's lists). Two cases that
    # read alike then (power[n=4] and power{n=4}) each carry 8 hex digits of a
    # hash of their listed name, and the job's number if even those agree.
    set(plain "${case}")
    string(REPLACE "[" "{" plain "${plain}")
    string(REPLACE "]" "}" plain "${plain}")
    string(REGEX REPLACE "[][()*+?|^$\\\\;]" "_" plain "${plain}")
    set(plain_${index} "${check}/${plain}")
    set(case_${index} "${case}")
    set(check_${index} "${check}")
    # How many jobs have this name (counted under a digest of it, so that any
    # name can key a variable).
    string(SHA1 key "${check}/${plain}")
    if(DEFINED uses_${key})
      math(EXPR uses_${key} "${uses_${key}} + 1")
    else()
      set(uses_${key} 1)
    endif()
  endforeach()

  foreach(index RANGE 1 ${count})
    set(plain "${plain_${index}}")
    set(case "${case_${index}}")
    set(check "${check_${index}}")
    string(SHA1 key "${plain}")
    string(SHA256 case_hash "${case}")
    set(name "${plain}")
    if(uses_${key} GREATER 1)
      string(SUBSTRING "${case_hash}" 0 8 short_hash)
      set(name "${plain}~${short_hash}")
      string(SHA1 key "${name}")
      if(DEFINED taken_${key})
        set(name "${name}~${index}")
      endif()
      set(taken_${key} 1)
    endif()
    set(name "${warpcheck_prefix}${name}")

    # The evidence file: <case>__<check> with letters and digits kept, the rest
    # '_' (as the GoogleTest adapter names it); a name over 255 bytes keeps its
    # first bytes and 16 hex digits of a hash of the case name; and the job's
    # number after a name that an earlier job already has.
    string(REGEX REPLACE "[^A-Za-z0-9]" "_" file_case "${case}")
    string(REGEX REPLACE "_+$" "" file_case "${file_case}")
    set(file "${file_case}__${check}")
    string(LENGTH "${file}.html" file_length)
    if(file_length GREATER 255)
      string(LENGTH "${check}" check_length)
      math(EXPR keep "255 - 5 - 2 - ${check_length} - 17")
      string(SUBSTRING "${file_case}" 0 ${keep} file_case)
      string(SUBSTRING "${case_hash}" 0 16 long_hash)
      set(file "${file_case}_${long_hash}__${check}")
    endif()
    if(DEFINED warpcheck_file_${file})
      set(file "${file}_${index}")
    endif()
    set(warpcheck_file_${file} 1)
    add_test("${name}" "${warpcheck_program}" ${warpcheck_args} --shard ${index}/${count} --color never
      --progress none --settings-from-environment --report-on-failure "${evidence}/${file}.html")
    set_tests_properties("${name}" PROPERTIES LABELS "${check};${warpcheck_labels}"
      WORKING_DIRECTORY "${warpcheck_directory}" ${warpcheck_properties})
  endforeach()
endfunction()
_warpcheck_add_job_tests()
