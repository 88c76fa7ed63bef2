# The bench view's browser tests (tests/ui/*.test.mjs): node's test runner drives Debian's chromium
# through puppeteer-core (npm, tests/ui/package-lock.json; tools/setup --with-test-deps installs
# both). One chromium at a time needs the machine's two cores: the quiet resource group.
find_program(GPSEMU_NODE node)
file(GLOB GPSEMU_UI_TESTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/ui/*.test.mjs)
foreach(file ${GPSEMU_UI_TESTS})
  get_filename_component(stem ${file} NAME_WE)
  add_test(NAME ui_${stem} COMMAND ${GPSEMU_NODE} --test ${file} WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/ui)
  set_tests_properties(ui_${stem} PROPERTIES TIMEOUT 180 LABELS e2e RESOURCE_GROUPS quiet:2
                       ENVIRONMENT "GPSEMU_BINARY=$<TARGET_FILE:gpsemu>")
endforeach()
