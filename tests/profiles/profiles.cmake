# The receiver profiles (data/profiles, tools/update-profiles) are what the tool writes: none edited
# by hand, none stale against its log, its sources.toml entry or the calibration (docs/noise-and-calibration.md).
#  - profiles.current: every profile's digest (its text, its log's bytes, its sources entry) matches,
#    every sources entry has its profile and every profile its entry; no gpsemu run.
#  - profiles.regenerate: four profiles rebuilt from their logs with this build's gpsemu (calibrate at
#    seed 1, the 8x run's fidelity at seed 7) equal the shipped ones byte for byte: a change of the
#    calibration shows here. The cheapest four (3 s of CPU); `tools/update-profiles --check` rebuilds
#    all eight (about 45 s of CPU) and is what to run after changing the calibration.
#  - profiles.edits_are_caught: a copy of the profiles with one number changed fails both checks.
# The two that run gpsemu calibrate are CPU-bound: one slot of the `cpu` resource each, in the idle
# scheduling class (chrt, util-linux), as the CPU-bound test executables (tests/CMakeLists.txt).
set(GPSEMU_PROFILES_TOOL ${PROJECT_SOURCE_DIR}/tools/update-profiles)
add_test(NAME profiles.current COMMAND python3 ${GPSEMU_PROFILES_TOOL} --check-digests)
set_tests_properties(profiles.current PROPERTIES LABELS unit)

add_test(NAME profiles.regenerate
         COMMAND chrt --idle 0 python3 ${GPSEMU_PROFILES_TOOL} --gpsemu $<TARGET_FILE:gpsemu> --check
                 --only ublox-neo-m9n,trimble-rtk-fixed,ublox-max-m8q,sirfstar-v)
set_tests_properties(profiles.regenerate PROPERTIES LABELS e2e TIMEOUT ${GPSEMU_TEST_TIMEOUT_S} RESOURCE_GROUPS cpu:1)

add_test(NAME profiles.edits_are_caught
         COMMAND chrt --idle 0 ${CMAKE_COMMAND} -DTOOL=${GPSEMU_PROFILES_TOOL} -DGPSEMU=$<TARGET_FILE:gpsemu>
                 -DPROFILES=${PROJECT_SOURCE_DIR}/data/profiles -DCOPY=${CMAKE_CURRENT_BINARY_DIR}/profiles-edited
                 -P ${CMAKE_CURRENT_LIST_DIR}/edits_are_caught.cmake)
set_tests_properties(profiles.edits_are_caught PROPERTIES LABELS e2e TIMEOUT ${GPSEMU_TEST_TIMEOUT_S} RESOURCE_GROUPS cpu:1)
