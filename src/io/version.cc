// The version string; the only file that includes the git version (a header
// the build writes from `git describe` when it changes:
// cmake/GitVersion.cmake), so that a new commit does not invalidate the
// compiler cache of the library.
#include "io/results_file.h"

#include "systole_git_version.h"

#ifndef SYSTOLE_VERSION
#  define SYSTOLE_VERSION "unknown"
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
