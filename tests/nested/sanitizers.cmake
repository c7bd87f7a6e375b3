# Builds the tree with AddressSanitizer and UndefinedBehaviorSanitizer in a scratch build and runs
# its test suite there (the nested checks themselves are not repeated). -O1 and line tables only
# (-g1) instead of RelWithDebInfo's default -O2 -g: the build is most of this test's time (the whole
# test went from 1435 s to 1196 s in CI runs on 2 cores); stack traces keep their file and line.
# The outer build's generator (Ninja in CI: it compiles a library's files while the libraries
# below it link, where Make waits target by target).
if(NOT GEN)
  set(GEN "Unix Makefiles")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SRC} -B ${WORK} -G ${GEN} -DCMAKE_BUILD_TYPE=RelWithDebInfo
                        "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
                        -DRAYPROOF_SANITIZE=ON -DRAYPROOF_BUILD_BENCH=OFF -DRAYPROOF_INSTALL=OFF
                        -DRAYPROOF_NESTED_CHECKS=OFF COMMAND_ERROR_IS_FATAL ANY)
execute_process(COMMAND ${CMAKE_COMMAND} --build ${WORK} -j2 COMMAND_ERROR_IS_FATAL ANY)
# Left out here, beside the install consumers: four tests that repeat, at a larger size, code that
# other tests run under the sanitizers too. They were 175 of the 812 test-seconds of this tree
# (6 to 7 times their time in the Release tree):
# - CasterCheck.CountsEqualABruteForceExactTally (75 s): the judge's tally against a brute force on
#   4 meshes; the other CasterCheck tests run the same judge on the same kind of rays;
# - WindingBenchCli.OpenMeshBesideItsClosedOriginal (65 s): mostly `bench contains`'s closed-mesh
#   part on 75k lattice points; its open-mesh rows' code runs in the Winding and WindingFuzz tests;
# - CrossingsBrute.LatticeBoxes and .BumpyBoxes (35 s): .SmallShapes and .HoledBoxesAndSoups stay.
set(SLOW_REPEATS "install_consumer|CasterCheck.CountsEqualABruteForceExactTally|WindingBenchCli.OpenMeshBesideItsClosedOriginal|CrossingsBrute.LatticeBoxes|CrossingsBrute.BumpyBoxes")
execute_process(COMMAND ${CMAKE_CTEST_COMMAND} --test-dir ${WORK} --output-on-failure -j2 -E "${SLOW_REPEATS}"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the sanitizer build's tests failed")
endif()
