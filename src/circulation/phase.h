#pragma once

/// @file
/// The four phases of the cardiac cycle and the valve events between them.

namespace systole::Circulation
{
  /// Phase of the ventricle. The integer values are the codes written to the
  /// results file (time-series column "phase").
  enum class Phase : int
  {
    filling                   = 0, ///< mitral valve open, aortic closed
    isovolumetric_contraction = 1, ///< both valves closed, volume constant
    ejection                  = 2, ///< aortic valve open, mitral closed
    isovolumetric_relaxation  = 3  ///< both valves closed, volume constant
  };

  /// Number of phases (the codes are 0 ... n_phases - 1).
  constexpr unsigned int n_phases = 4;

  /// The code of @p phase as written to output files.
  constexpr int
  code(const Phase phase)
  {
    return static_cast<int>(phase);
  }

  /// Snake-case name of @p phase ("filling", "isovolumetric_contraction", ...).
  constexpr const char *
  name(const Phase phase)
  {
    constexpr const char *names[n_phases] = {"filling",
                                             "isovolumetric_contraction",
                                             "ejection",
                                             "isovolumetric_relaxation"};
    return names[code(phase)];
  }

  /// What happens at the transition @p from -> @p to, in words ("mitral
  /// valve closes", ...); "invalid transition" for pairs the cycle never
  /// takes.
  constexpr const char *
  event_name(const Phase from, const Phase to)
  {
    if (from == Phase::filling && to == Phase::isovolumetric_contraction)
      return "mitral valve closes";
    if (from == Phase::isovolumetric_contraction && to == Phase::ejection)
      return "aortic valve opens";
    if (from == Phase::isovolumetric_contraction && to == Phase::filling)
      return "mitral valve reopens: the aortic valve did not open (weak "
             "contraction)";
    if (from == Phase::ejection && to == Phase::isovolumetric_relaxation)
      return "aortic valve closes";
    if (from == Phase::isovolumetric_relaxation && to == Phase::filling)
      return "mitral valve opens";
    return "invalid transition";
  }
} // namespace systole::Circulation
