# Headers must compile on their own: for each header of a folder, compile a
# translation unit that includes only that header. A subfolder that builds its
# own library (with its own dependencies) checks its headers itself: name it
# after EXCLUDE. A test, so built only with WARPCHECK_BUILD_TESTS: the release
# build compiles what the validate command needs and nothing else.
function(warpcheck_check_headers folder)
  # The sanitizer build compiles the same headers as the test build, whose
  # self-checks suffice.
  if(NOT WARPCHECK_BUILD_TESTS OR WARPCHECK_SANITIZE)
    return()
  endif()
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "EXCLUDE")
  file(GLOB_RECURSE headers CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/${folder}/*.h")
  foreach(excluded IN LISTS arg_EXCLUDE)
    list(FILTER headers EXCLUDE REGEX "^${PROJECT_SOURCE_DIR}/${folder}/${excluded}/")
  endforeach()
  set(sources "")
  foreach(header IN LISTS headers)
    file(RELATIVE_PATH rel "${PROJECT_SOURCE_DIR}" "${header}")
    string(MAKE_C_IDENTIFIER "${rel}" stem)
    set(tu "${CMAKE_CURRENT_BINARY_DIR}/header_check/${stem}.cpp")
    file(CONFIGURE OUTPUT "${tu}" CONTENT "#include \"${rel}\"\n")
    list(APPEND sources "${tu}")
  endforeach()
  if(sources)
    string(MAKE_C_IDENTIFIER "${folder}" target)
    add_library(header_check_${target} OBJECT ${sources})
    # One header per translation unit is the point: never batched into a unity source.
    set_target_properties(header_check_${target} PROPERTIES UNITY_BUILD OFF)
    target_link_libraries(header_check_${target} PRIVATE ${arg_UNPARSED_ARGUMENTS} warpcheck_options)
    # Whether a header compiles on its own does not depend on optimisation, and
    # its inline code is checked optimised where a source uses it: -O0 saves a
    # quarter of each of these ~140 compiles (1.26 s -> 0.95 s for bsdf_checks.h).
    target_compile_options(header_check_${target} PRIVATE -O0)
  endif()
endfunction()
