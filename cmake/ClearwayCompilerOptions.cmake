# Warnings, sanitizers and ccache, applied per target through clearway_target_defaults().

find_program(CLEARWAY_CCACHE ccache)
if(CLEARWAY_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_C_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CLEARWAY_CCACHE})
endif()

function(clearway_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Wcast-align -Woverloaded-virtual)
  if(CLEARWAY_SANITIZE)
    string(REPLACE ";" "," sanitizers "${CLEARWAY_SANITIZE}")
    target_compile_options(${target} PRIVATE -fsanitize=${sanitizers} -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=${sanitizers})
  endif()
endfunction()
