# gpsemu as a library: the installed CMake package used by a separate example project, and the
# Python module's tests (pytest; its exit status 5, "no tests collected", fails like any other).
# In a GPSEMU_SANITIZE build the installed libraries are instrumented, so the consumer links the
# sanitizer runtimes too.
add_test(NAME library.package_consumer
         COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR}
                 -DCONSUMER_SOURCE=${CMAKE_CURRENT_SOURCE_DIR}/package_consumer
                 -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/package_consumer
                 -DGENERATOR=${CMAKE_GENERATOR}
                 "-DCONSUMER_LINK_FLAGS=$<$<BOOL:${GPSEMU_SANITIZE}>:-fsanitize=address,undefined>"
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/package_consumer/run.cmake)
set_tests_properties(library.package_consumer PROPERTIES TIMEOUT 600 RUN_SERIAL TRUE LABELS e2e)

if(TARGET gpsemu_python)
  add_test(NAME python.gpsemu
           COMMAND ${GPSEMU_PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_SOURCE_DIR}/python)
  set_tests_properties(python.gpsemu PROPERTIES TIMEOUT 300 LABELS e2e
    ENVIRONMENT "PYTHONPATH=${GPSEMU_PYTHON_DIR};GPSEMU_BINARY=$<TARGET_FILE:gpsemu>")
endif()
