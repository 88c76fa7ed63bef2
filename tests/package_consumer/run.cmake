# cmake -DBUILD_DIR=... -DCONSUMER_SOURCE=... -DWORK_DIR=... -DGENERATOR=... [-DCONSUMER_CXX=...]
#       [-DCONSUMER_LINK_FLAGS=...]
#       [-DPYTHON=python3] -P run.cmake
# Installs the gpsemu build into WORK_DIR/prefix, then configures, builds and runs the example
# consumer against it with find_package(gpsemu) (CMAKE_PREFIX_PATH = that prefix only).
# CONSUMER_CXX: the C++ compiler of the gpsemu build (an instrumented library needs its own runtime).
# CONSUMER_LINK_FLAGS: linker flags for the consumer (the sanitizer runtimes, for an instrumented build).
# PYTHON (when the Python module is built): imports the installed module from
# WORK_DIR/prefix/lib/python3/dist-packages with PYTHONPATH set to it, and checks its version.
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(JOIN " " cmd ${ARGN})
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
step(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
foreach(f include/gpsemu/emulator/library/gpsemu.hpp include/gpsemu/nmea/parse.hpp)
  if(NOT EXISTS ${WORK_DIR}/prefix/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# In the library directory: lib/<multiarch> on Debian, lib elsewhere.
file(GLOB config ${WORK_DIR}/prefix/lib/cmake/gpsemu/gpsemuConfig.cmake ${WORK_DIR}/prefix/lib/*/cmake/gpsemu/gpsemuConfig.cmake)
if(NOT config)
  message(FATAL_ERROR "not installed: lib/[<multiarch>/]cmake/gpsemu/gpsemuConfig.cmake")
endif()
set(consumer_cxx)
if(CONSUMER_CXX)
  set(consumer_cxx -DCMAKE_CXX_COMPILER=${CONSUMER_CXX})
endif()
step(${CMAKE_COMMAND} -S ${CONSUMER_SOURCE} -B ${WORK_DIR}/build -G ${GENERATOR}
     -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON
     "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_LINK_FLAGS}" ${consumer_cxx})
step(${CMAKE_COMMAND} --build ${WORK_DIR}/build -j 1)
step(${WORK_DIR}/build/consumer)
message("${step_output}")
if(NOT step_output MATCHES "\\$G[PN]RMC,120000\\.00,A,[^\n]*\n\\$G[PN]GGA,120000\\.00,4304\\.[0-9]+,N,08924\\.[0-9]+,W,1,"
   OR NOT step_output MATCHES "gpsemu [0-9]+\\.[0-9]+\\.[0-9]+: 3 GGA parsed")
  message(FATAL_ERROR "unexpected consumer output")
endif()
string(REGEX MATCH "gpsemu ([0-9]+\\.[0-9]+\\.[0-9]+): 3 GGA" _ "${step_output}")
set(version ${CMAKE_MATCH_1})
message("package consumer: OK")

if(PYTHON)
  set(site ${WORK_DIR}/prefix/lib/python3/dist-packages)
  file(GLOB module ${site}/gpsemu*.so)
  if(NOT module)
    message(FATAL_ERROR "Python module not installed in ${site}")
  endif()
  # PYTHONPATH comes before every site directory: the module found is the installed one. (No ';' in
  # the code: CMake would split the argument there.)
  step(${CMAKE_COMMAND} -E env "PYTHONPATH=${site}" ${PYTHON} -c
       "import gpsemu\nassert gpsemu.__file__.startswith('${site}/'), gpsemu.__file__\nprint(gpsemu.__version__)")
  if(NOT step_output STREQUAL "${version}\n")
    message(FATAL_ERROR "installed Python module: version '${step_output}', the library's ${version}")
  endif()
  message("installed Python module: ${step_output}")
endif()
