// The version string; the only file compiled with the git version, so that a
// new commit does not invalidate the compiler cache of the whole library.
#include "io/results_file.h"

#ifndef SYSTOLE_VERSION
#  define SYSTOLE_VERSION "unknown"
#endif
#ifndef SYSTOLE_GIT_VERSION
#  define SYSTOLE_GIT_VERSION "unknown"
#endif

namespace systole::IO
{
  std::string
  code_version()
  {
    return std::string("systole ") + SYSTOLE_VERSION + " (" +
           SYSTOLE_GIT_VERSION + ")";
  }
} // namespace systole::IO
