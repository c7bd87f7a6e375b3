# Install rules and the exported CMake package, one component per public target:
#   find_package(rayproof CONFIG REQUIRED COMPONENTS core certified verify scene)
#   target_link_libraries(app PRIVATE rayproof::certified)
# plus one pkg-config file per component (rayproof.pc is core). docs/library.md describes both.
#
# The component table below is the only hand-written part. Everything else is derived from the
# targets' link interfaces when this file runs (after every target exists): the static libraries
# below the public API that a component's archive needs (exported as rayproof::internal_*), which
# components a component needs, the packages to find for it, and the -l flags of its .pc file.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# component:targets. The first target is the component's own (exported as rayproof::COMPONENT), the
# others keep their EXPORT_NAME (else their name without "rayproof_"); a|b takes the first of a, b
# that this build has.
set(_rp_table
  "core:rayproof_core"
  "certified:rayproof_certified|rayproof_certified_gmp"
  "verify:rayproof_check|rayproof_verify"
  "scene:rayproof_scene,rayproof_scene_certified"
  "caster_check:rayproof_caster_check")
# Link-interface items that only the build uses: warning flags, header-only libraries linked
# privately. They are dropped from the installed interface.
set(_rp_build_only rayproof_warnings nlohmann_json::nlohmann_json)
# Packages behind imported targets in the link interface: how the config file finds each, and what
# pkg-config and Debian call it. GMP and MPFR come from find_library (libraries linked by path in
# the build, by the rayproof_ext:: targets that the config file defines in an installation).
set(_rp_pkg_CGAL_find "CGAL CONFIG")
set(_rp_pkg_CGAL_pc gmp mpfr)
set(_rp_pkg_CGAL_deb libcgal-dev)
set(_rp_pkg_TBB_find "TBB CONFIG")
set(_rp_pkg_TBB_pc tbb)
set(_rp_pkg_TBB_deb libtbb-dev)
set(_rp_pkg_fmt_find "fmt CONFIG")
set(_rp_pkg_fmt_pc fmt)
set(_rp_pkg_fmt_deb libfmt-dev)
set(_rp_pkg_TinyGLTF_find "TinyGLTF CONFIG")
set(_rp_pkg_TinyGLTF_pc tinygltf)
set(_rp_pkg_TinyGLTF_deb libtinygltf-dev)
set(_rp_pkg_Threads_find Threads)
set(_rp_pkg_Threads_pc "")
set(_rp_pkg_Threads_deb libc6-dev)
set(_rp_lib_gmp_deb libgmp-dev)
set(_rp_lib_gmpxx_deb libgmp-dev)
set(_rp_lib_mpfr_deb libmpfr-dev)

# Every rule here is in the install component "rayproof" (install components are not find_package
# components): `cmake --install build --component rayproof` and the .deb take exactly these files,
# not other install rules of the tree (the Python module goes to the interpreter's site directory).
set(RAYPROOF_INSTALL_COMPONENT rayproof)
set(RAYPROOF_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rayproof)
set(RAYPROOF_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# The components this build has (core always; the others need RAYPROOF_BUILD_TOOLS).
set(_rp_components)
set(_rp_component_targets)
foreach(_entry IN LISTS _rp_table)
  string(REPLACE ":" ";" _entry "${_entry}")
  list(POP_FRONT _entry _c)
  string(REPLACE "," ";" _wanted "${_entry}")
  set(_rp_${_c}_targets)
  foreach(_alternatives IN LISTS _wanted)
    string(REPLACE "|" ";" _alternatives "${_alternatives}")
    foreach(_t IN LISTS _alternatives)
      if(TARGET ${_t})
        list(APPEND _rp_${_c}_targets ${_t})
        break()
      endif()
    endforeach()
  endforeach()
  if(NOT _rp_${_c}_targets)
    continue()
  endif()
  list(APPEND _rp_components ${_c})
  list(APPEND _rp_component_targets ${_rp_${_c}_targets})
  foreach(_t IN LISTS _rp_${_c}_targets)
    set(_rp_target_${_t}_component ${_c})
    get_target_property(_name ${_t} EXPORT_NAME)
    if(NOT _name)
      string(REGEX REPLACE "^rayproof_" "" _name ${_t})
    endif()
    list(GET _rp_${_c}_targets 0 _main)
    if(_t STREQUAL _main)
      set(_name ${_c})
    endif()
    set_target_properties(${_t} PROPERTIES EXPORT_NAME ${_name})
  endforeach()
endforeach()

# _rp_link_items(TARGET OUT): what TARGET's link interface names, $<LINK_ONLY:> unwrapped, ALIAS
# targets resolved, other generator expressions and directory markers skipped.
function(_rp_link_items tgt out)
  get_target_property(_items ${tgt} INTERFACE_LINK_LIBRARIES)
  set(_r)
  foreach(_i IN LISTS _items)
    if(_i MATCHES "^\\$<LINK_ONLY:([^$<>]+)>$")
      set(_i ${CMAKE_MATCH_1})
    endif()
    if(_i MATCHES "^::@" OR _i MATCHES "\\$<" OR _i STREQUAL "")
      continue()
    endif()
    if(_i MATCHES "^rayproof::" AND TARGET ${_i})
      get_target_property(_aliased ${_i} ALIASED_TARGET)
      if(_aliased)
        set(_i ${_aliased})
      endif()
    endif()
    list(APPEND _r ${_i})
  endforeach()
  set(${out} ${_r} PARENT_SCOPE)
endfunction()

# Libraries linked by path or name that the installed config file provides as rayproof_ext:: targets.
set(_rp_ext_lib_regex "(^|/)(lib)?(gmpxx|gmp|mpfr)(\\.so|\\.a)?$")

# Walk every component's link closure: internal libraries (our static libraries that are not
# components), components needed, external packages and libraries, and our archives in link order.
set(_rp_internal)
foreach(_c IN LISTS _rp_components)
  set(_todo ${_rp_${_c}_targets})
  set(_seen)
  set(_rp_${_c}_requires)
  set(_rp_${_c}_packages)
  set(_rp_${_c}_libs)
  set(_rp_${_c}_system)  # system libraries by name, linker flags
  set(_archives)
  while(_todo)
    list(POP_FRONT _todo _t)
    if(_t IN_LIST _seen)
      continue()
    endif()
    list(APPEND _seen ${_t})
    if(_t IN_LIST _rp_build_only)
      continue()
    elseif(NOT _t MATCHES "^rayproof::" AND _t MATCHES "^([A-Za-z0-9_]+)::")
      # An imported target (found in a subdirectory, so maybe not visible here): its package.
      list(APPEND _rp_${_c}_packages ${CMAKE_MATCH_1})
    elseif(TARGET ${_t})
      get_target_property(_type ${_t} TYPE)
      get_target_property(_imported ${_t} IMPORTED)
      if(_imported)
        list(APPEND _rp_${_c}_packages ${_t})
        continue()
      elseif(_t IN_LIST _rp_component_targets AND NOT _t IN_LIST _rp_${_c}_targets)
        list(APPEND _rp_${_c}_requires ${_rp_target_${_t}_component})
        continue()
      elseif(NOT _t IN_LIST _rp_component_targets)
        if(NOT _type MATCHES "^(STATIC|INTERFACE)_LIBRARY$")
          message(FATAL_ERROR "rayproof install: component ${_c} links ${_t} (${_type}), which is "
                  "neither a component, a static or interface library nor build-only (cmake/Install.cmake)")
        endif()
        list(APPEND _rp_internal ${_t})
      endif()
      _rp_link_items(${_t} _next)
      if(_type STREQUAL "STATIC_LIBRARY")
        list(APPEND _archives ${_t})
        set(_deps_${_t})
        foreach(_n IN LISTS _next)
          if(TARGET ${_n} AND NOT _n IN_LIST _rp_build_only AND NOT _n MATCHES "::")
            get_target_property(_nt ${_n} TYPE)
            if(_nt STREQUAL "STATIC_LIBRARY" AND (_n IN_LIST _rp_${_c}_targets OR NOT _n IN_LIST _rp_component_targets))
              list(APPEND _deps_${_t} ${_n})
            endif()
          endif()
        endforeach()
      endif()
      list(APPEND _todo ${_next})
    elseif(_t MATCHES "${_rp_ext_lib_regex}")
      list(APPEND _rp_${_c}_libs ${CMAKE_MATCH_3})
    elseif(_t MATCHES "^-" OR _t MATCHES "^[A-Za-z0-9_+.-]+$")
      # A system library by name (dl, pthread, m) or a linker flag: exported as it is.
      list(APPEND _rp_${_c}_system ${_t})
    else()
      message(WARNING "rayproof install: component ${_c} links '${_t}' by path; the installed package "
              "names that path (cmake/Install.cmake could map it to a target found at install time)")
      list(APPEND _rp_${_c}_system ${_t})
    endif()
  endwhile()
  foreach(_v requires packages libs system)
    list(REMOVE_DUPLICATES _rp_${_c}_${_v})
  endforeach()
  # Link order: an archive comes before every archive it links (GNU ld reads archives once).
  set(_rp_${_c}_archives)
  while(_archives)
    foreach(_a IN LISTS _archives)
      set(_needed OFF)
      foreach(_b IN LISTS _archives)
        if(_a IN_LIST _deps_${_b})
          set(_needed ON)
        endif()
      endforeach()
      if(NOT _needed)
        list(APPEND _rp_${_c}_archives ${_a})
        list(REMOVE_ITEM _archives ${_a})
        break()
      endif()
    endforeach()
    if(_needed)
      message(FATAL_ERROR "rayproof install: archives ${_archives} of component ${_c} link each other")
    endif()
  endwhile()
endforeach()
list(REMOVE_DUPLICATES _rp_internal)
# Packages and libraries of the required components are the required components' business.
foreach(_c IN LISTS _rp_components)
  foreach(_r IN LISTS _rp_${_c}_requires)
    foreach(_v packages libs system)
      if(_rp_${_r}_${_v})
        list(REMOVE_ITEM _rp_${_c}_${_v} ${_rp_${_r}_${_v}})
      endif()
    endforeach()
  endforeach()
endforeach()

set(_rp_source_include_targets)  # targets whose interface names a source directory
# Installed link interfaces: build-only items wrapped in $<BUILD_INTERFACE:>, GMP and MPFR by path
# replaced with rayproof_ext:: targets, source-tree include directories made build-only.
foreach(_t IN LISTS _rp_component_targets _rp_internal)
  get_target_property(_items ${_t} INTERFACE_LINK_LIBRARIES)
  if(_items)
    set(_new)
    foreach(_i IN LISTS _items)
      set(_bare ${_i})
      if(_i MATCHES "^\\$<LINK_ONLY:([^$<>]+)>$")
        set(_bare ${CMAKE_MATCH_1})
      endif()
      if(_bare IN_LIST _rp_build_only)
        list(APPEND _new "$<BUILD_INTERFACE:${_i}>")
      elseif(NOT TARGET ${_bare} AND _bare MATCHES "${_rp_ext_lib_regex}")
        list(APPEND _new "$<BUILD_INTERFACE:${_i}>" "$<INSTALL_INTERFACE:$<LINK_ONLY:rayproof_ext::${CMAKE_MATCH_3}>>")
      else()
        list(APPEND _new "${_i}")
      endif()
    endforeach()
    set_property(TARGET ${_t} PROPERTY INTERFACE_LINK_LIBRARIES "${_new}")
  endif()
  get_target_property(_dirs ${_t} INTERFACE_INCLUDE_DIRECTORIES)
  if(_dirs)
    set(_new)
    foreach(_d IN LISTS _dirs)
      set(_in_tree OFF)
      if(NOT _d MATCHES "^\\$<")
        cmake_path(IS_PREFIX PROJECT_SOURCE_DIR "${_d}" NORMALIZE _in_src)
        cmake_path(IS_PREFIX PROJECT_BINARY_DIR "${_d}" NORMALIZE _in_bin)
        if(_in_src OR _in_bin)
          set(_in_tree ON)
        endif()
      endif()
      if(NOT _in_tree)
        list(APPEND _new "${_d}")
      else()
        list(APPEND _new "$<BUILD_INTERFACE:${_d}>")
        list(APPEND _rp_source_include_targets ${_t})
      endif()
    endforeach()
    set_property(TARGET ${_t} PROPERTY INTERFACE_INCLUDE_DIRECTORIES "${_new}")
  endif()
endforeach()

# Headers below the public API that users of a component include (ideally none: the public API is
# include/rayproof/), with every header of the tree they include, found by following their
# #include "..." lines. Installed under include/rayproof/internal/ with their source-relative paths
# ("io/case_file.h"); the targets whose interface named a source directory get that include directory.
set(_rp_internal_entries verify/check.h)
set(_rp_internal_includedir ${CMAKE_INSTALL_INCLUDEDIR}/rayproof/internal)
set(_rp_headers)
set(_rp_todo ${_rp_internal_entries})
while(_rp_todo)
  list(POP_FRONT _rp_todo _h)
  if(_h IN_LIST _rp_headers OR _h MATCHES "^rayproof/")
    continue()
  endif()
  set(_file)
  foreach(_root ${PROJECT_SOURCE_DIR}/src ${PROJECT_SOURCE_DIR})
    if(NOT _file AND EXISTS ${_root}/${_h})
      set(_file ${_root}/${_h})
    endif()
  endforeach()
  if(NOT _file)
    message(FATAL_ERROR "rayproof install: header ${_h} (included by an installed header) not found")
  endif()
  list(APPEND _rp_headers ${_h})
  get_filename_component(_dir ${_h} DIRECTORY)
  install(FILES ${_file} DESTINATION ${_rp_internal_includedir}/${_dir} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
  file(STRINGS ${_file} _includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(_line IN LISTS _includes)
    if(_line MATCHES "\"([^\"]+)\"")
      list(APPEND _rp_todo ${CMAKE_MATCH_1})
    endif()
  endforeach()
endwhile()
if(_rp_headers)
  foreach(_t IN LISTS _rp_source_include_targets)
    set_property(TARGET ${_t} APPEND PROPERTY INTERFACE_INCLUDE_DIRECTORIES
                 "$<INSTALL_INTERFACE:${_rp_internal_includedir}>")
  endforeach()
endif()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rayproof DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT ${RAYPROOF_INSTALL_COMPONENT})

# One export set per component, one for the internal libraries; the config file loads the ones asked for.
foreach(_c IN LISTS _rp_components)
  install(TARGETS ${_rp_${_c}_targets} EXPORT rayproof_${_c}_targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
  install(EXPORT rayproof_${_c}_targets NAMESPACE rayproof:: FILE rayproof_${_c}_targets.cmake
          DESTINATION ${RAYPROOF_CMAKE_DIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
endforeach()
if(_rp_internal)
  foreach(_t IN LISTS _rp_internal)
    string(REGEX REPLACE "^rayproof_" "" _n ${_t})
    set_target_properties(${_t} PROPERTIES EXPORT_NAME internal_${_n})
  endforeach()
  install(TARGETS ${_rp_internal} EXPORT rayproof_internal_targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
  install(EXPORT rayproof_internal_targets NAMESPACE rayproof:: FILE rayproof_internal_targets.cmake
          DESTINATION ${RAYPROOF_CMAKE_DIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
endif()

# The config file's component table, in an order where every component follows the ones it needs.
set(_rp_ordered)
set(_rp_left ${_rp_components})
while(_rp_left)
  set(_progress OFF)
  foreach(_c IN LISTS _rp_left)
    set(_ready ON)
    foreach(_r IN LISTS _rp_${_c}_requires)
      if(NOT _r IN_LIST _rp_ordered)
        set(_ready OFF)
      endif()
    endforeach()
    if(_ready)
      list(APPEND _rp_ordered ${_c})
      list(REMOVE_ITEM _rp_left ${_c})
      set(_progress ON)
    endif()
  endforeach()
  if(NOT _progress)
    message(FATAL_ERROR "rayproof install: components ${_rp_left} need each other")
  endif()
endwhile()
set(RAYPROOF_COMPONENT_TABLE "set(_rayproof_components ${_rp_ordered})\n")
set(_rp_used_packages)
foreach(_c IN LISTS _rp_ordered)
  set(_finds)
  foreach(_p IN LISTS _rp_${_c}_packages)
    if(NOT DEFINED _rp_pkg_${_p}_find)
      message(WARNING "rayproof install: component ${_c} needs package ${_p}, which cmake/Install.cmake "
              "does not list: the config file calls find_package(${_p}), pkg-config and the .deb miss it")
      set(_rp_pkg_${_p}_find ${_p})
      set(_rp_pkg_${_p}_deb "its -dev package")
    endif()
    list(APPEND _rp_used_packages ${_p})
    list(APPEND _finds "${_p}")
  endforeach()
  set(_internal OFF)
  foreach(_a IN LISTS _rp_${_c}_archives)
    if(_a IN_LIST _rp_internal)
      set(_internal ON)
    endif()
  endforeach()
  string(APPEND RAYPROOF_COMPONENT_TABLE
    "set(_rayproof_${_c}_requires ${_rp_${_c}_requires})\n"
    "set(_rayproof_${_c}_packages ${_finds})\n"
    "set(_rayproof_${_c}_libraries ${_rp_${_c}_libs})\n"
    "set(_rayproof_${_c}_internal ${_internal})\n")
endforeach()
set(RAYPROOF_PACKAGE_FINDS "")
list(REMOVE_DUPLICATES _rp_used_packages)
foreach(_p IN LISTS _rp_used_packages)
  string(APPEND RAYPROOF_PACKAGE_FINDS "set(_rayproof_find_${_p} ${_rp_pkg_${_p}_find})\n"
                                       "set(_rayproof_deb_${_p} ${_rp_pkg_${_p}_deb})\n")
endforeach()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rayproofConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rayproofConfig.cmake
  INSTALL_DESTINATION ${RAYPROOF_CMAKE_DIR})
# Not ARCH_INDEPENDENT: the components are compiled static libraries.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rayproofConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rayproofConfig.cmake ${PROJECT_BINARY_DIR}/rayproofConfigVersion.cmake
  DESTINATION ${RAYPROOF_CMAKE_DIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})

include(${CMAKE_CURRENT_LIST_DIR}/InstallPkgConfig.cmake)

if(TARGET rayproof)  # the tool
  install(TARGETS rayproof RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${RAYPROOF_INSTALL_COMPONENT})
endif()

# For cmake/Package.cmake: the Debian packages the components need to be found and linked.
set(RAYPROOF_DEB_DEV_DEPENDS)
foreach(_c IN LISTS _rp_components)
  foreach(_p IN LISTS _rp_${_c}_packages)
    list(APPEND RAYPROOF_DEB_DEV_DEPENDS ${_rp_pkg_${_p}_deb})
  endforeach()
  foreach(_l IN LISTS _rp_${_c}_libs)
    list(APPEND RAYPROOF_DEB_DEV_DEPENDS ${_rp_lib_${_l}_deb})
  endforeach()
endforeach()
list(REMOVE_DUPLICATES RAYPROOF_DEB_DEV_DEPENDS)

# cpack -G DEB (cmake/Package.cmake).
include(${CMAKE_CURRENT_LIST_DIR}/Package.cmake)
