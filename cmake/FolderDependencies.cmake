# Run as `cmake -DSOURCE_DIR=... -P FolderDependencies.cmake` (the ctest
# folder_dependencies): fails on an #include of a folder that the including
# folder may not depend on. The allowed edges have no circle, so each library
# builds from the ones below it:
#   sampling -> (nothing)   chi2 -> (nothing)   reports -> (nothing)
#   validate -> sampling, chi2, reports
# "warpcheck/" is the generated version header of the results library.
# Inside validate/, each room (subfolder) may include only the rooms below it
# (validate/README.md says what each room holds):
#   api -> (nothing)   lanes -> api   checks -> lanes, api   cases -> lanes, api
#   run -> checks, api   samples -> run, checks, api   cli -> samples, run, checks, api
#   trust -> run, checks, api   gtest -> cli, run, checks, api   python -> samples, cli, run, checks, api
# A file at validate/'s top level, or in a room without a rule here, fails.
cmake_minimum_required(VERSION 3.25)
set(allowed_sampling sampling)
set(allowed_chi2 chi2)
set(allowed_reports reports warpcheck)
set(allowed_validate validate sampling chi2 reports warpcheck)

# The rooms of validate/ each room may include (itself included).
set(rooms_api api)
set(rooms_lanes lanes api)
set(rooms_checks checks lanes api)
set(rooms_cases cases lanes api)
set(rooms_run run checks api)
set(rooms_samples samples run checks api)
set(rooms_cli cli samples run checks api)
set(rooms_trust trust run checks api)
set(rooms_gtest gtest cli run checks api)
set(rooms_python python samples cli run checks api)

set(problems "")
foreach(folder sampling chi2 reports validate)
  file(GLOB_RECURSE files "${SOURCE_DIR}/${folder}/*.h" "${SOURCE_DIR}/${folder}/*.cpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[^\"/]+/")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[^\"]*\"([^\"/]+)/.*$" "\\1" included "${line}")
      if(NOT included IN_LIST allowed_${folder})
        file(RELATIVE_PATH rel "${SOURCE_DIR}" "${file}")
        list(JOIN allowed_${folder} ", " allowed)
        string(APPEND problems "  ${rel}: ${line}  (${folder}/ may include: ${allowed})\n")
      endif()
    endforeach()
  endforeach()
endforeach()
# Includes between the rooms of validate/.
file(GLOB_RECURSE files RELATIVE "${SOURCE_DIR}/validate" "${SOURCE_DIR}/validate/*.h" "${SOURCE_DIR}/validate/*.cpp")
foreach(rel IN LISTS files)
  if(NOT rel MATCHES "^([^/]+)/")
    string(APPEND problems "  validate/${rel}: a file at validate/'s top level (put it in a room, validate/README.md)\n")
    continue()
  endif()
  set(room "${CMAKE_MATCH_1}")
  if(NOT DEFINED rooms_${room})
    string(APPEND problems "  validate/${rel}: room ${room}/ has no rule (add rooms_${room} to cmake/FolderDependencies.cmake)\n")
    continue()
  endif()
  file(STRINGS "${SOURCE_DIR}/validate/${rel}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"validate/")
  foreach(line IN LISTS includes)
    if(line MATCHES "\"validate/([^\"/]+)/" AND CMAKE_MATCH_1 IN_LIST rooms_${room})
      continue()
    endif()
    list(JOIN rooms_${room} ", " allowed)
    string(APPEND problems "  validate/${rel}: ${line}  (validate/${room}/ may include the rooms: ${allowed})\n")
  endforeach()
endforeach()

if(problems)
  message(FATAL_ERROR "Includes across folders that the layout forbids:\n${problems}")
endif()
message(STATUS "Folder dependencies: validate -> sampling, chi2, reports; no other edges; validate's rooms in order")
