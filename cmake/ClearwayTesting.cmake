# clearway_add_gtest(NAME SOURCES a.cpp b.cpp LIBRARIES lib... [LABELS label...])
# One GoogleTest executable registered as one ctest test. Tests find the real scans through
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
  add_test(NAME ${name} COMMAND ${name})
  set_tests_properties(${name} PROPERTIES LABELS "${ARG_LABELS}")
endfunction()
