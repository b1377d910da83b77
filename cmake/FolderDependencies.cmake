# Run as `cmake -DSOURCE_DIR=... -P FolderDependencies.cmake` (the ctest
# folder_dependencies): fails on an #include of a folder that the including
# folder may not depend on. The allowed edges have no circle, so each library
# builds from the ones below it:
#   sampling -> (nothing)   chi2 -> (nothing)   reports -> (nothing)
#   validate -> sampling, chi2, reports
# "warpcheck/" is the generated version header of the results library.
cmake_minimum_required(VERSION 3.25)
set(allowed_sampling sampling)
set(allowed_chi2 chi2)
set(allowed_reports reports warpcheck)
set(allowed_validate validate sampling chi2 reports warpcheck)

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
if(problems)
  message(FATAL_ERROR "Includes across folders that the layout forbids:\n${problems}")
endif()
message(STATUS "Folder dependencies: validate -> sampling, chi2, reports; no other edges")
