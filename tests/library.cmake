# gpsemu as a library: the installed CMake package used by a separate example project (and the
# installed Python module imported from the prefix), and the Python module's tests (pytest; its exit
# status 5, "no tests collected", fails like any other).
# In a GPSEMU_SANITIZE build the installed libraries are instrumented, so the consumer links the
# sanitizer runtimes too, with the compiler that built them.
add_test(NAME library.package_consumer
         COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${CMAKE_BINARY_DIR}
                 -DCONSUMER_SOURCE=${CMAKE_CURRENT_SOURCE_DIR}/package_consumer
                 -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/package_consumer
                 -DGENERATOR=${CMAKE_GENERATOR}
                 -DCONSUMER_CXX=${CMAKE_CXX_COMPILER}
                 "-DCONSUMER_LINK_FLAGS=$<$<BOOL:${GPSEMU_SANITIZE}>:-fsanitize=address,undefined>"
                 "-DPYTHON=$<$<TARGET_EXISTS:gpsemu_python>:${GPSEMU_PYTHON_EXECUTABLE}>"
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/package_consumer/run.cmake)
set_tests_properties(library.package_consumer PROPERTIES TIMEOUT 600 RUN_SERIAL TRUE LABELS e2e)

if(TARGET gpsemu_python)
  add_test(NAME python.gpsemu
           COMMAND ${GPSEMU_PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_SOURCE_DIR}/python)
  set_tests_properties(python.gpsemu PROPERTIES TIMEOUT 300 LABELS e2e
    ENVIRONMENT "PYTHONPATH=${GPSEMU_PYTHON_DIR};GPSEMU_BINARY=$<TARGET_FILE:gpsemu>")
endif()

# The Debian packages (tools/packaging): built with CPack from this build tree, installed with
# apt-get and purged again when root (the machine is compared before and after), else unpacked
# with dpkg -x into the test's directory; what they install is run (tests/package/).
find_program(GPSEMU_DPKG_SHLIBDEPS dpkg-shlibdeps)
if(GPSEMU_DPKG_SHLIBDEPS AND TARGET gpsemu_python)
  add_test(NAME package.deb_install
           COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/package/deb_install_test.sh ${CMAKE_BINARY_DIR} ${PROJECT_SOURCE_DIR}
                   ${CMAKE_CURRENT_BINARY_DIR}/package_deb ${GPSEMU_PYTHON_EXECUTABLE} ${CMAKE_GENERATOR})
  set_tests_properties(package.deb_install PROPERTIES TIMEOUT 900 RUN_SERIAL TRUE LABELS e2e)
endif()
