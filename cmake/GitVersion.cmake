# Writes OUTPUT (a header defining SYSTOLE_GIT_VERSION, the `git describe` of SOURCE_DIR) at
# every build, and touches it only when the version changed: a new commit or a change of the
# working tree recompiles src/io/version.cc alone, and the banner never shows a stale version.
execute_process(COMMAND git describe --always --dirty --tags
                WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE version OUTPUT_STRIP_TRAILING_WHITESPACE
                ERROR_QUIET)
if(NOT version)
  set(version "unknown")
endif()
set(content "#define SYSTOLE_GIT_VERSION \"${version}\"\n")
set(old "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
endif()
if(NOT old STREQUAL content)
  file(WRITE ${OUTPUT} "${content}")
endif()
