# `cpack -G DEB` in the build directory: one .deb with the headers, the component libraries, the CMake
# package, the pkg-config files and the rayproof tool, for Debian 12 (the package names below are
# bookworm's). Included at the end of cmake/Install.cmake (it needs RAYPROOF_DEB_DEV_DEPENDS).
set(CPACK_PACKAGE_NAME rayproof)
set(CPACK_PACKAGE_VENDOR "rayproof")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Ray intersection kernels verified against exact arithmetic (C++20 library and tool)")
set(CPACK_PACKAGE_DESCRIPTION
    "Header-only floating-point and certified ray intersection kernels; static libraries for certified and exact answers (GMP, MPFR), the checker of a kernel against exact, and mesh ray casting (TBB); their CMake package and pkg-config files; the rayproof command-line tool.")
set(RAYPROOF_DEB_MAINTAINER "rayproof maintainers <rayproof@localhost>" CACHE STRING
    "Maintainer field of the .deb (cpack -G DEB)")
set(CPACK_PACKAGE_CONTACT "${RAYPROOF_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${RAYPROOF_DEB_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
# The install component of cmake/Install.cmake only (build dir; project; component; subdirectory).
set(CPACK_INSTALL_CMAKE_PROJECTS "${PROJECT_BINARY_DIR};${PROJECT_NAME};${RAYPROOF_INSTALL_COMPONENT};/")
# No dpkg-shlibdeps (dpkg-dev is not a build dependency): the tool's shared libraries listed by hand,
# then the -dev packages the components' find_package and link lines need (from Install.cmake).
set(_rp_deb_runtime)
if(TARGET rayproof)
  set(_rp_deb_runtime libc6 libstdc++6 libgcc-s1 libgmp10 libmpfr6 libtbb12 libfmt9 libpng16-16)
  get_property(_rp_gltf GLOBAL PROPERTY RAYPROOF_HAVE_TINYGLTF)  # src/CMakeLists.txt
  if(_rp_gltf)
    list(APPEND _rp_deb_runtime libtinygltf2d)
  endif()
  find_package(embree 3 QUIET)
  if(embree_FOUND)
    list(APPEND _rp_deb_runtime libembree3-3)
  endif()
endif()
set(_rp_deb_depends ${_rp_deb_runtime} ${RAYPROOF_DEB_DEV_DEPENDS})
list(REMOVE_DUPLICATES _rp_deb_depends)
list(JOIN _rp_deb_depends ", " CPACK_DEBIAN_PACKAGE_DEPENDS)
include(CPack)
