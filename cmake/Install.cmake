# Install the header-only core and export it as a CMake package:
#   find_package(rayproof CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE rayproof::core)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rayproof DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS rayproof_core EXPORT rayproofTargets)
install(EXPORT rayproofTargets NAMESPACE rayproof:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rayproof)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rayproofConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rayproofConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rayproof)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rayproofConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion ARCH_INDEPENDENT)
install(FILES ${PROJECT_BINARY_DIR}/rayproofConfig.cmake ${PROJECT_BINARY_DIR}/rayproofConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rayproof)
if(TARGET rayproof)
  install(TARGETS rayproof RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
