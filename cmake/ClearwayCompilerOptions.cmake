# Warnings, sanitizers and ccache, applied per target through clearway_target_defaults().

option(CLEARWAY_WERROR "Treat compiler warnings in Clearway's own targets as errors (CI turns it on)"
       OFF)
option(CLEARWAY_FUZZ "Build the libFuzzer harnesses of tests/fuzz (clang only; see scripts/fuzz)" OFF)
if(CLEARWAY_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "CLEARWAY_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++), not "
                      "${CMAKE_CXX_COMPILER_ID}")
endif()

find_program(CLEARWAY_CCACHE ccache)
if(CLEARWAY_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_C_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
endif()

function(clearway_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Woverloaded-virtual)
  if(CLEARWAY_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(CLEARWAY_FUZZ)
    # Coverage feedback for libFuzzer in every library the harnesses call.
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
  if(CLEARWAY_SANITIZE)
    string(REPLACE ";" "," sanitizers "${CLEARWAY_SANITIZE}")
    target_compile_options(${target} PRIVATE -fsanitize=${sanitizers} -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=${sanitizers})
  endif()
endfunction()
