# The installed package as a downstream project sees it, from the already built tree BUILD (no rebuild):
#   MODE=prefix: `cmake --install BUILD --prefix WORK/prefix --component rayproof`; the checks of the
#                config file (a missing package, a missing library, an unknown component, an optional
#                component); consumer_all built with find_package against the prefix; a pkg-config
#                build of all of it.
#   MODE=deb:    `cpack -G DEB` in BUILD; the .deb's metadata and files; dpkg-deb -x into WORK/root;
#                consumer_all, and pkg-config builds of core + certified and of scene alone, against
#                it; the packaged rayproof tool runs.
# LIBDIR is the tree's CMAKE_INSTALL_LIBDIR (relative), CXX the compiler the tree was built with,
# GMP_LIBRARY the GMP it linked (hidden to test the message for a missing library).
# Consumers are built without optimization (a compile check and a run, not a benchmark).
cmake_minimum_required(VERSION 3.20)
foreach(v SRC BUILD WORK MODE CXX LIBDIR GMP_LIBRARY)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run.cmake needs -D${v}=...")
  endif()
endforeach()
set(CONSUMER ${SRC}/tests/consumer_all)
# The consumers check certified::intersect over the shared sample (data/sample.txt, sample.expected).
set(ENV{RAYPROOF_SAMPLE_DIR} ${SRC}/data)
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK})

include(${CMAKE_CURRENT_LIST_DIR}/../consumer_run.cmake)

# consumer_all against PREFIX with find_package, then both programs run.
function(build_consumer prefix dir)
  run(${CMAKE_COMMAND} -S ${CONSUMER} -B ${dir} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX}
      -DCMAKE_BUILD_TYPE= -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE)
  run(${CMAKE_COMMAND} --build ${dir} -j2)
  foreach(exe consumer_certified consumer_all)
    run(${dir}/${exe})
    message(STATUS "${exe}:\n${run_out}")
  endforeach()
endfunction()

# A consumer built with pkg-config's flags only (no CMake package): MODULES are the .pc files, MAIN
# and SOURCES the consumer's files, OUT the program, which must run and pass.
function(build_pkgconfig prefix libdir modules out main)
  find_program(PKG_CONFIG NAMES pkg-config pkgconf REQUIRED)
  set(ENV{PKG_CONFIG_PATH} ${prefix}/${libdir}/pkgconfig)
  run(${PKG_CONFIG} --cflags --libs ${modules})
  string(STRIP "${run_out}" flags)
  message(STATUS "pkg-config --cflags --libs ${modules}: ${flags}")
  separate_arguments(flags UNIX_COMMAND "${flags}")
  list(TRANSFORM ARGN PREPEND ${CONSUMER}/)
  run(${CXX} -std=c++20 ${CONSUMER}/${main} ${ARGN} ${flags} -o ${out})
  run(${out})
  message(STATUS "${out}:\n${run_out}")
endfunction()

# A consumer project asking for COMPONENTS after the CMake code PRE (which hides a dependency) must
# fail to configure, with a message matching every regex after PRE.
function(expect_configure_failure name components pre)
  set(dir ${WORK}/${name})
  file(MAKE_DIRECTORY ${dir}/src)
  file(WRITE ${dir}/src/CMakeLists.txt
       "cmake_minimum_required(VERSION 3.20)\nproject(c LANGUAGES CXX)\n${pre}\n"
       "find_package(rayproof CONFIG REQUIRED COMPONENTS ${components})\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${dir}/src -B ${dir}/build -DCMAKE_PREFIX_PATH=${WORK}/prefix
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "${name}: configuring with COMPONENTS ${components} succeeded, it must fail")
  endif()
  string(REGEX REPLACE "[ \n]+" " " err "${err}")
  foreach(re IN LISTS ARGN)
    if(NOT err MATCHES "${re}")
      message(FATAL_ERROR "${name}: the error does not match '${re}':\n${err}")
    endif()
  endforeach()
  string(FIND "${err}" "Reason given by package: " from)
  math(EXPR from "${from} + 25")
  string(SUBSTRING "${err}" ${from} -1 reason)
  message(STATUS "${name}: fails as it should: ${reason}")
endfunction()

if(MODE STREQUAL "prefix")
  run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix --component rayproof)
  # A required component whose dependency is missing (a package, a library), an unknown component.
  expect_configure_failure(no_tbb "core;scene" "set(CMAKE_DISABLE_FIND_PACKAGE_TBB ON)"
                           "component 'scene' needs package TBB" "libtbb-dev")
  get_filename_component(gmp_dir ${GMP_LIBRARY} DIRECTORY)
  set(hide ${gmp_dir})
  if(gmp_dir MATCHES "^/usr(/lib.*)$")  # merged /usr: /lib is /usr/lib
    list(APPEND hide ${CMAKE_MATCH_1})
  endif()
  expect_configure_failure(no_gmp "certified" "set(CMAKE_IGNORE_PATH ${hide})"
                           "component 'certified' needs.* library gmp " "libgmp-dev")
  expect_configure_failure(unknown "core;bogus" "" "no component 'bogus'")
  # An optional component whose dependency is missing: found FALSE, its target absent, no error.
  file(MAKE_DIRECTORY ${WORK}/optional/src)
  file(WRITE ${WORK}/optional/src/CMakeLists.txt [=[
cmake_minimum_required(VERSION 3.20)
project(c LANGUAGES CXX)
find_package(rayproof CONFIG REQUIRED COMPONENTS core OPTIONAL_COMPONENTS scene)
if(rayproof_scene_FOUND OR TARGET rayproof::scene OR NOT rayproof_core_FOUND OR NOT TARGET rayproof::core)
  message(FATAL_ERROR "optional scene without TBB: scene ${rayproof_scene_FOUND}, core ${rayproof_core_FOUND}")
endif()
]=])
  run(${CMAKE_COMMAND} -S ${WORK}/optional/src -B ${WORK}/optional/build -DCMAKE_PREFIX_PATH=${WORK}/prefix
      -DCMAKE_DISABLE_FIND_PACKAGE_TBB=ON)
  build_consumer(${WORK}/prefix ${WORK}/consumer)
  # Every component with pkg-config (the .deb below: core + certified only).
  build_pkgconfig(${WORK}/prefix ${LIBDIR} "rayproof-certified;rayproof-verify;rayproof-scene"
                  ${WORK}/pkgconfig_consumer_all main_all.cpp core.cpp certified.cpp verify.cpp scene.cpp)
elseif(MODE STREQUAL "deb")
  get_filename_component(cmake_bin ${CMAKE_COMMAND} DIRECTORY)
  find_program(CPACK NAMES cpack HINTS ${cmake_bin} REQUIRED)
  find_program(DPKG_DEB dpkg-deb REQUIRED)
  execute_process(COMMAND ${CPACK} -G DEB -B ${WORK}/deb WORKING_DIRECTORY ${BUILD}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  file(GLOB deb ${WORK}/deb/*.deb)
  if(NOT rc EQUAL 0 OR NOT deb)
    message(FATAL_ERROR "cpack -G DEB failed (${rc}):\n${out}\n${err}")
  endif()
  file(REMOVE_RECURSE ${WORK}/deb/_CPack_Packages)  # cpack's staging copy
  run(${DPKG_DEB} --field ${deb} Package Version Depends)
  message(STATUS "${deb}:\n${run_out}")
  foreach(dep libgmp-dev libmpfr-dev libtbb-dev)
    if(NOT run_out MATCHES "Depends:.*${dep}")
      message(FATAL_ERROR "the .deb does not depend on ${dep}")
    endif()
  endforeach()
  run(${DPKG_DEB} -x ${deb} ${WORK}/root)
  set(prefix ${WORK}/root/usr)
  set(libdir ${LIBDIR})
  foreach(f bin/rayproof include/rayproof/triangle.h ${libdir}/cmake/rayproof/rayproofConfig.cmake
            ${libdir}/cmake/rayproof/rayproofConfigVersion.cmake ${libdir}/pkgconfig/rayproof.pc
            ${libdir}/pkgconfig/rayproof-certified.pc)
    if(NOT EXISTS ${prefix}/${f})
      message(FATAL_ERROR "the .deb has no /usr/${f}")
    endif()
  endforeach()
  run(${prefix}/bin/rayproof methods)
  message(STATUS "packaged rayproof methods:\n${run_out}")
  # A scene command of the packaged tool.
  run(${prefix}/bin/rayproof cast --help)
  if(NOT run_out MATCHES "--mesh|scene")
    message(FATAL_ERROR "the packaged rayproof cast --help printed no scene options:\n${run_out}")
  endif()
  build_consumer(${prefix} ${WORK}/consumer)
  build_pkgconfig(${prefix} ${libdir} rayproof-certified ${WORK}/pkgconfig_consumer_certified
                  main_certified.cpp core.cpp certified.cpp)
  build_pkgconfig(${prefix} ${libdir} rayproof-scene ${WORK}/pkgconfig_consumer_scene main_scene.cpp scene.cpp)
else()
  message(FATAL_ERROR "MODE must be prefix or deb, not '${MODE}'")
endif()
