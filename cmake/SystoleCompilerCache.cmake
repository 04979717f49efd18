# ccache and a fast linker when present; neither is required.
find_program(SYSTOLE_CCACHE ccache)
if(SYSTOLE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  set(CMAKE_CXX_COMPILER_LAUNCHER ${SYSTOLE_CCACHE})
  set(CMAKE_C_COMPILER_LAUNCHER ${SYSTOLE_CCACHE})
  message(STATUS "Using ccache: ${SYSTOLE_CCACHE}")
endif()

find_program(SYSTOLE_MOLD mold)
if(SYSTOLE_MOLD)
  add_link_options(-fuse-ld=mold)
  message(STATUS "Linking with mold")
endif()
