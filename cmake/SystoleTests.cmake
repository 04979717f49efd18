# Helpers to register run tests: a .prm through the systole app, checked by a script.
find_program(SYSTOLE_MPIEXEC NAMES mpirun mpiexec REQUIRED)
set(SYSTOLE_MPIEXEC_FLAGS --allow-run-as-root --oversubscribe)

# systole_add_run_test(NAME n PRM file.prm [MPI ranks] [APP target] [PREPARE script args...]
#                      CHECK script args...)
# Runs `systole PRM` (or the executable target APP, e.g. systole-fibres; under mpirun when
# MPI > 1) in a private directory (the working folder, emptied first), then the CHECK command
# (a Python script of tests/runs, run with the project's venv Python) on the results. PRM is
# relative to the current source folder unless absolute. PREPARE (a Python script and its
# arguments) runs in the working folder before the app, e.g. to write an input file there.
# The app's standard output is also saved as stdout.txt in the working folder.
function(systole_add_run_test)
  cmake_parse_arguments(RT "" "NAME;PRM;MPI;APP" "CHECK;PREPARE" ${ARGN})
  if(NOT RT_MPI)
    set(RT_MPI 1)
  endif()
  if(NOT RT_APP)
    set(RT_APP systole-app)
  endif()
  if(NOT IS_ABSOLUTE ${RT_PRM})
    set(RT_PRM ${CMAKE_CURRENT_SOURCE_DIR}/${RT_PRM})
  endif()
  set(workdir ${CMAKE_CURRENT_BINARY_DIR}/${RT_NAME})
  add_test(NAME run.${RT_NAME}
    COMMAND ${CMAKE_COMMAND}
      -DSYSTOLE=$<TARGET_FILE:${RT_APP}>
      -DMPIEXEC=${SYSTOLE_MPIEXEC} -DRANKS=${RT_MPI}
      -DPRM=${RT_PRM}
      -DWORKDIR=${workdir}
      -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
      -DPYTHON=${Python3_EXECUTABLE}
      "-DPREPARE=${RT_PREPARE}"
      "-DCHECK=${RT_CHECK}"
      -P ${PROJECT_SOURCE_DIR}/cmake/RunTest.cmake)
  set_tests_properties(run.${RT_NAME} PROPERTIES LABELS run PROCESSORS ${RT_MPI} TIMEOUT 300)
endfunction()

# systole_add_error_test(NAME n PRM file.prm EXPECT regex [MPI ranks] [PREPARE script args...]
#                        [CHECK script args...])
# The app must exit non-zero and print exactly one line on stderr matching EXPECT. Without
# CHECK it must leave no results folder (input errors stop before any output); with CHECK
# (a run that fails midway) the CHECK command must pass on what it left. PREPARE as for
# systole_add_run_test.
function(systole_add_error_test)
  cmake_parse_arguments(ET "" "NAME;PRM;EXPECT;MPI" "CHECK;PREPARE" ${ARGN})
  if(NOT ET_MPI)
    set(ET_MPI 1)
  endif()
  add_test(NAME run.error_${ET_NAME}
    COMMAND ${CMAKE_COMMAND}
      -DSYSTOLE=$<TARGET_FILE:systole-app>
      -DMPIEXEC=${SYSTOLE_MPIEXEC} -DRANKS=${ET_MPI}
      -DPRM=${ET_PRM}
      -DWORKDIR=${CMAKE_CURRENT_BINARY_DIR}/error_${ET_NAME}
      -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
      "-DEXPECT=${ET_EXPECT}"
      -DPYTHON=${Python3_EXECUTABLE}
      "-DPREPARE=${ET_PREPARE}"
      "-DCHECK=${ET_CHECK}"
      -P ${PROJECT_SOURCE_DIR}/cmake/ExpectError.cmake)
  set_tests_properties(run.error_${ET_NAME} PROPERTIES LABELS run PROCESSORS ${ET_MPI} TIMEOUT 120)
endfunction()
