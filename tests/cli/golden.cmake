# Golden-file regression tests (like gpsd's .log/.chk pairs): a fixed scenario, seed and start
# time must produce exactly the checked-in bytes. Regenerate deliberately with tools/update-golden.
set(GPSEMU_GOLDEN_DIR ${PROJECT_SOURCE_DIR}/tests/golden)
file(GLOB GPSEMU_GOLDEN_ARGS CONFIGURE_DEPENDS ${GPSEMU_GOLDEN_DIR}/*.args)
foreach(args_file ${GPSEMU_GOLDEN_ARGS})
  get_filename_component(name ${args_file} NAME_WE)
  add_test(NAME golden.${name}
           COMMAND ${CMAKE_COMMAND} -DGPSEMU=$<TARGET_FILE:gpsemu> -DARGS_FILE=${args_file}
                   -DEXPECTED=${GPSEMU_GOLDEN_DIR}/${name}.nmea -DACTUAL=${CMAKE_CURRENT_BINARY_DIR}/${name}.nmea
                   -P ${CMAKE_CURRENT_LIST_DIR}/golden_compare.cmake)
  set_tests_properties(golden.${name} PROPERTIES LABELS e2e)
endforeach()
