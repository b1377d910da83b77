# Installs warpcheck as a CMake package: find_package(warpcheck) gives
# warpcheck::validate (the library), warpcheck::main (a ready main() for
# programs that validate their own warps), warpcheck::register17 (the include
# path of validate/api/register17.h, for C++17 files that register warps),
# warpcheck::sampling (the warps), warpcheck::reports (the report writers),
# warpcheck::results (the result model), warpcheck::gtest (GoogleTest
# assertions, validate/gtest/warpcheck_gtest.h) and the CMake function
# warpcheck_discover_tests (cmake/warpcheckDiscoverTests.cmake).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(warpcheck_targets warpcheck_options warpcheck_sampling warpcheck_chi2 warpcheck_results warpcheck_reports
    warpcheck_validate warpcheck_cases warpcheck_main warpcheck_register17)
set_target_properties(warpcheck_sampling PROPERTIES EXPORT_NAME sampling)
set_target_properties(warpcheck_chi2 PROPERTIES EXPORT_NAME chi2)
set_target_properties(warpcheck_results PROPERTIES EXPORT_NAME results)
set_target_properties(warpcheck_reports PROPERTIES EXPORT_NAME reports)
set_target_properties(warpcheck_validate PROPERTIES EXPORT_NAME validate)
set_target_properties(warpcheck_main PROPERTIES EXPORT_NAME main)
set_target_properties(warpcheck_cases PROPERTIES EXPORT_NAME cases)
set_target_properties(warpcheck_register17 PROPERTIES EXPORT_NAME register17)
set_target_properties(warpcheck_options PROPERTIES EXPORT_NAME options)
# warpcheck::gtest, where GoogleTest was found (validate/CMakeLists.txt); the
# package then finds GoogleTest too.
set(WARPCHECK_WITH_GTEST OFF)
if(TARGET warpcheck_gtest)
  set(WARPCHECK_WITH_GTEST ON)
  list(APPEND warpcheck_targets warpcheck_gtest)
  set_target_properties(warpcheck_gtest PROPERTIES EXPORT_NAME gtest)
endif()

install(TARGETS validate RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# One shard of a run on a cluster or CI engine, the index from the engine's
# own variable (validate/cli/README.md, "Sharding on a cluster").
install(PROGRAMS validate/cli/warpcheck_shard.sh DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME warpcheck_shard)
install(TARGETS ${warpcheck_targets}
  EXPORT warpcheckTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  OBJECTS DESTINATION ${CMAKE_INSTALL_LIBDIR}/warpcheck)
# Only the headers a renderer writes against, and what they include (cmake/PublicHeaders.cmake).
include(${PROJECT_SOURCE_DIR}/cmake/PublicHeaders.cmake)
warpcheck_public_headers("${PROJECT_SOURCE_DIR}" warpcheck_installed_headers)
foreach(header IN LISTS warpcheck_installed_headers)
  get_filename_component(folder "${header}" DIRECTORY)
  install(FILES "${header}" DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/warpcheck/${folder})
endforeach()
# The include paths of 0.1 (<validate/external.h>, ...), kept for one release:
# each forwards to its header in validate/api/ with a deprecation warning that
# names it (validate/api/old_paths/, validate/api/CHANGELOG.md).
file(GLOB warpcheck_old_path_headers CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/validate/api/old_paths/*.h")
install(FILES ${warpcheck_old_path_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/warpcheck/validate)
install(FILES "${WARPCHECK_GENERATED_INCLUDE_DIR}/warpcheck/version.h"
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/warpcheck/warpcheck)
install(EXPORT warpcheckTargets NAMESPACE warpcheck:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/warpcheck)

configure_package_config_file(cmake/warpcheckConfig.cmake.in
  "${CMAKE_CURRENT_BINARY_DIR}/warpcheckConfig.cmake"
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/warpcheck)
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/warpcheckConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/warpcheckConfig.cmake"
              "${CMAKE_CURRENT_BINARY_DIR}/warpcheckConfigVersion.cmake"
              cmake/warpcheckDiscoverTests.cmake cmake/warpcheckAddJobTests.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/warpcheck)
