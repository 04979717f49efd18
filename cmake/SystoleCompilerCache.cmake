# ccache and a fast linker when present; neither is required.
option(SYSTOLE_PRECOMPILED_HEADERS "Precompile the common deal.II headers" ON)
find_program(SYSTOLE_CCACHE ccache)
if(SYSTOLE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  # With precompiled headers ccache must hash the .gch instead of the header's text
  # (-fpch-preprocess), ignore the macros and mtimes of a precompiled header built a moment
  # earlier (ccache manual, "Precompiled headers"), and hash a checksum of the .gch rather than
  # the .gch itself: cmake/ccache_launcher.sh.
  set(_launcher ${SYSTOLE_CCACHE})
  if(SYSTOLE_PRECOMPILED_HEADERS)
    set(_launcher sh ${CMAKE_CURRENT_SOURCE_DIR}/cmake/ccache_launcher.sh ${SYSTOLE_CCACHE})
    add_compile_options(-fpch-preprocess)
  endif()
  set(CMAKE_CXX_COMPILER_LAUNCHER ${_launcher})
  set(CMAKE_C_COMPILER_LAUNCHER ${_launcher})
  message(STATUS "Using ccache: ${SYSTOLE_CCACHE}")
endif()

find_program(SYSTOLE_MOLD mold)
if(SYSTOLE_MOLD)
  add_link_options(-fuse-ld=mold)
  message(STATUS "Linking with mold")
endif()
