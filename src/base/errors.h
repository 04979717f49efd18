#pragma once

#include <deal.II/base/exceptions.h>

#include <string>

/// @file
/// Typed exceptions. User-caused and physical problems use AssertThrow (never
/// Assert). The recoverable ones below are caught by the time loop, which cuts
/// the step; all others propagate to main(), which prints one line on rank 0
/// and exits non-zero. A recoverable failure must be decided collectively
/// (every rank throws, or none does).

namespace systole
{
  /// Newton's method did not converge; the caller may cut the load or time
  /// step.
  DeclException3(ExcNewtonDidNotConverge,
                 std::string,
                 unsigned int,
                 double,
                 << "Newton's method did not converge (" << arg1 << ") after "
                 << arg2 << " iterations (relative residual " << arg3 << ").");

  /// An element was inverted (det F <= 0) at some quadrature point.
  DeclExceptionMsg(ExcInvertedElement,
                   "An element was inverted (det F <= 0): the load step was "
                   "too large or the mesh too coarse.");

  /// Text of an exception without deal.II's file/line banner, folded onto one
  /// line.
  std::string
  one_line_message(const std::exception &e);
} // namespace systole
