# The installed include folder holds what a renderer writes against and nothing
# else: the entry headers below (the case description and registration, the
# C++17 header, the GoogleTest adapter) and every project header they include,
# found here by following their #include lines. The rest of the tree is private.
# tests/external_example/run_example.sh checks the installed count (at most 30)
# and that a private header is not installed.
set(warpcheck_public_entry_headers
  validate/api/external.h
  validate/api/bsdf_grid.h
  validate/api/light_case.h
  validate/api/register17.h
  validate/gtest/warpcheck_gtest.h)

# Sets `out_var` to the entry headers and the project headers they include,
# transitively, as paths relative to `source_dir`, sorted.
function(warpcheck_public_headers source_dir out_var)
  set(pending ${warpcheck_public_entry_headers})
  set(found "")
  while(pending)
    list(POP_FRONT pending header)
    if(header IN_LIST found)
      continue()
    endif()
    list(APPEND found "${header}")
    file(STRINGS "${source_dir}/${header}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+[\"<][^\">]+[\">]")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[^\"<]*[\"<]([^\">]+)[\">].*$" "\\1" included "${line}")
      if(EXISTS "${source_dir}/${included}" AND NOT IS_DIRECTORY "${source_dir}/${included}")
        list(APPEND pending "${included}")
      endif()
    endforeach()
  endwhile()
  list(SORT found)
  set(${out_var} ${found} PARENT_SCOPE)
endfunction()
