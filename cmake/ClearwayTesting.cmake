include(GoogleTest)

# clearway_add_gtest(NAME SOURCES a.cpp b.cpp LIBRARIES lib... [LABELS label...])
# One GoogleTest executable; each of its test cases becomes its own ctest test, named
# "NAME.Suite.Case", so cases run in parallel and a failure is named. The cases are listed when
# ctest runs (PRE_TEST), so building never runs the test binaries. Tests find the real scans through
# CLEARWAY_REAL_DATA_DIR and skip with a message when it is absent.
function(clearway_add_gtest name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBRARIES;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBRARIES} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE
    CLEARWAY_REAL_DATA_DIR="${CLEARWAY_REAL_DATA_DIR}"
    CLEARWAY_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    CLEARWAY_CLI="$<TARGET_FILE:clearway-cli>")
  clearway_target_defaults(${name})
  gtest_discover_tests(${name} TEST_PREFIX "${name}." DISCOVERY_MODE PRE_TEST
                       DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${ARG_LABELS}")
endfunction()

# clearway_add_qt_test(NAME SOURCES a.cpp LABELS label... [PLATFORM offscreen|xcb] [LAUNCHER cmd...])
# One Qt Test executable (AUTOMOC, linked to clearway::ui) registered as one ctest test, run on the
# given Qt platform, optionally through a launcher (xvfb-run for rendering tests).
function(clearway_add_qt_test name)
  cmake_parse_arguments(ARG "" "PLATFORM" "SOURCES;LABELS;LAUNCHER" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  set_target_properties(${name} PROPERTIES AUTOMOC ON)
  target_link_libraries(${name} PRIVATE clearway::ui Qt5::Test)
  target_compile_definitions(${name} PRIVATE CLEARWAY_SAMPLES_DIR="${CLEARWAY_SAMPLES_DIR}")
  add_dependencies(${name} clearway_samples)
  clearway_target_defaults(${name})
  add_test(NAME ${name} COMMAND ${ARG_LAUNCHER} $<TARGET_FILE:${name}>)
  set_tests_properties(${name} PROPERTIES LABELS "${ARG_LABELS}" ENVIRONMENT "QT_QPA_PLATFORM=${ARG_PLATFORM}")
endfunction()
