#pragma once

#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace systole::Electrophysiology
{
  /// Where a stimulus acts: a box, a sphere, or a layer of given thickness
  /// along a named boundary part (e.g. the endocardium).
  struct StimulusRegion
  {
    enum class Shape
    {
      box,
      sphere,
      surface
    };

    Shape shape = Shape::box;

    dealii::Point<3> lower;  ///< box: corner with the smallest coordinates [mm]
    dealii::Point<3> upper;  ///< box: corner with the largest coordinates [mm]
    dealii::Point<3> centre; ///< sphere: centre [mm]
    double           radius = 0; ///< sphere: radius [mm]

    std::string boundary_part; ///< surface: name of the boundary part
    double      distance = 0;  ///< surface: layer thickness [mm]

    /// Whether @p p lies in the region (closed set). For a surface region,
    /// @p distance_to_surface is the distance of @p p to the boundary part
    /// [mm] (ignored by the other shapes).
    bool
    contains(const dealii::Point<3> &p,
             const double            distance_to_surface = 0) const;
  };

  /// One stimulus: a region, a time window and a current density,
  /// repeated every beat when the protocol has a period.
  struct Stimulus
  {
    std::string    name;
    StimulusRegion region;
    double         start     = 0; ///< onset in the first beat [ms]
    double         duration  = 0; ///< [ms], > 0
    double         amplitude = 0; ///< current density I_stim [µA/mm³]

    /// Whether the stimulus is on at time @p t [ms]: t in [start + k P,
    /// start + k P + duration) for some integer k >= 0, P = @p period; with
    /// P = 0 only k = 0.
    bool
    active(const double t, const double period) const;
  };

  /// The times in the open interval (@p t0, @p t1) at which any of
  /// @p stimuli switches on or off (period @p period, 0: once), sorted and
  /// without duplicates. The time integration ends its steps there, so that
  /// every step sees each stimulus either on or off throughout: the charge
  /// delivered is then exact and the Runge-Kutta order is kept.
  std::vector<double>
  switching_times(const std::vector<Stimulus> &stimuli,
                  const double                 period,
                  const double                 t0,
                  const double                 t1);

  /// Parse "Electrophysiology / Stimuli": stimuli separated by ';', each
  /// @code
  ///   <name>: <region> from <start> for <duration> at <amplitude>
  /// @endcode
  /// with <region> one of
  /// `box x0 y0 z0 x1 y1 z1`, `sphere x y z r`, `surface <part> <distance>`
  /// (numbers separated by spaces or commas; mm, ms, µA/mm³). Example (the
  /// Niederer et al. 2011 slab): `corner: box 0 0 0 1.5 1.5 1.5 from 0 for 2
  /// at 50`. Throws ExcMessage quoting the faulty item and the expected form.
  std::vector<Stimulus>
  parse_stimuli(const std::string &text);
} // namespace systole::Electrophysiology
