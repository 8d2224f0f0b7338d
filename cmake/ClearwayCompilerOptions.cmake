# Warnings, sanitizers and ccache, applied per target through clearway_target_defaults().

option(CLEARWAY_WERROR "Treat compiler warnings in Clearway's own targets as errors (CI turns it on)"
       OFF)
option(CLEARWAY_FUZZ "Build the libFuzzer harnesses of tests/fuzz (clang only; see scripts/fuzz)" OFF)
if(CLEARWAY_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "CLEARWAY_FUZZ needs clang (-DCMAKE_CXX_COMPILER=clang++), not "
                      "${CMAKE_CXX_COMPILER_ID}")
endif()

# The instruction set of Clearway's own code. x86-64-v2 (SSE4.2, POPCNT; every x86-64 processor
# since 2009) rounds with one instruction where the baseline calls a dozen (std::floor, std::ceil
# in every cell and triangle loop) and counts bits in one: 3.5 % fewer instructions per scan, maps
# byte-identical (no FMA, no reassociation: the same IEEE results). Used only when the compiler
# takes it and the build machine runs it; set it empty to build for any x86-64 (docs/PERFORMANCE.md).
set(CLEARWAY_ARCH "x86-64-v2" CACHE STRING "-march for Clearway's own code (empty: the compiler's default)")
set(CLEARWAY_ARCH_FLAG "")
if(CLEARWAY_ARCH AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  include(CheckCXXSourceRuns)
  set(CMAKE_REQUIRED_FLAGS "-march=${CLEARWAY_ARCH}")
  # The check's result is cached per architecture: another -DCLEARWAY_ARCH is checked afresh. It
  # asks the processor for x86-64-v2's features; a higher level is the builder's to vouch for.
  string(MAKE_C_IDENTIFIER "CLEARWAY_ARCH_RUNS_${CLEARWAY_ARCH}" arch_runs)
  check_cxx_source_runs("int main() { __builtin_cpu_init(); return __builtin_cpu_supports(\"sse4.2\") && __builtin_cpu_supports(\"popcnt\") ? 0 : 1; }"
                        ${arch_runs})
  unset(CMAKE_REQUIRED_FLAGS)
  if(${arch_runs})
    set(CLEARWAY_ARCH_FLAG "-march=${CLEARWAY_ARCH}")
  else()
    message(STATUS "Clearway: -march=${CLEARWAY_ARCH} not usable here; building for the default")
  endif()
endif()

find_program(CLEARWAY_CCACHE ccache)
if(CLEARWAY_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_C_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
endif()

function(clearway_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Woverloaded-virtual)
  if(CLEARWAY_ARCH_FLAG)
    target_compile_options(${target} PRIVATE ${CLEARWAY_ARCH_FLAG})
  endif()
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
