#pragma once

#include <deal.II/base/mpi.h>

#include "io/results_file.h"
#include "mechanics/problem.h"

#include "postprocess/aha_segments.h"
#include "postprocess/point_quantities.h"

#include <optional>
#include <string>
#include <vector>

namespace systole::Postprocess
{
  /// What a postprocessor may need beyond the point states; the manager
  /// computes only what the chosen postprocessors ask for.
  struct Needs
  {
    bool cardiac_frame = false; ///< the wall coordinates' frame per point
    bool segments      = false; ///< the AHA geometry and the cell segments
    bool vertices      = false; ///< reference and deformed vertices (LV wall)
    bool areas         = false; ///< deformed LV endocardial, epicardial areas
  };

  /// The state of the run at one accepted step, as the postprocessors see
  /// it. Per-point data are indexed [active cell index][quadrature point]
  /// (empty for cells of other ranks). Pointers are null where no
  /// postprocessor needs the data.
  struct StepData
  {
    double       time = 0; ///< [ms] (the load fraction of a load-stepped run)
    unsigned int beat = 0; ///< 0, 1, ... (0 without beats)
    double       beat_start = 0; ///< [ms]
    /// The cavity volume [mm^3]: NaN without a cavity.
    double cavity_volume = 0;
    /// Whether the (left) ventricle fills at this step, its mitral valve
    /// open, where a circulation says so (the heartbeat); unset otherwise.
    std::optional<bool>                                    filling;
    const std::vector<std::vector<Mechanics::PointState>> *points     = nullptr;
    const std::vector<std::vector<PointQuantities>>       *quantities = nullptr;
    /// The reference cardiac frame of every point (Needs::cardiac_frame).
    const std::vector<std::vector<CardiacFrame>> *frames   = nullptr;
    const AhaSegments                            *segments = nullptr;
    /// The segment (1 ... 17) of every point (of its reference position).
    const std::vector<std::vector<unsigned int>> *point_segments = nullptr;
    /// The reference and deformed vertices of the LV wall's cells.
    const std::vector<Mechanics::VertexState> *vertices = nullptr;
    /// Per active cell index, whether the cell is in the wall of the left
    /// ventricle (LvWall: the LV free wall and the septum of two
    /// ventricles); null: every cell (a left ventricle).
    const std::vector<bool> *wall_cells = nullptr;
    /// Deformed area of the LV endocardium [mm^2].
    double endocardial_area = 0;
    /// Deformed area of the LV wall's outer surface [mm^2]: the epicardium,
    /// for two ventricles that of the LV wall's cells and the septum's RV
    /// side (LvWall::outer_surface()).
    double   epicardial_area = 0;
    MPI_Comm comm            = MPI_COMM_WORLD;

    /// Whether the points of locally owned cell @p cell (active cell index)
    /// are in the wall of the left ventricle.
    bool
    in_wall(const unsigned int cell) const
    {
      return wall_cells == nullptr || (*wall_cells)[cell];
    }
  };

  /// One postprocessor: fields (a scalar per point of PointQuantities),
  /// /timeseries columns every step, /summary columns every beat.
  ///
  /// How to add one: write postprocess/<name>.{h,cc} deriving from this
  /// class, add one line to the table of postprocess/factory.cc, and a test
  /// in tests/unit/postprocess/ against an analytic deformation.
  class Postprocessor
  {
  public:
    virtual ~Postprocessor() = default;

    virtual Needs
    needs() const
    {
      return {};
    }

    /// Names of the scalar fields it writes.
    virtual std::vector<std::string>
    field_names() const
    {
      return {};
    }

    /// Value of field @p i (of field_names()) at a point.
    virtual double
    field_value(const unsigned int i, const PointQuantities &q) const
    {
      (void)i;
      (void)q;
      return 0;
    }

    /// Every accepted step, the first being the reference state: append
    /// /timeseries columns (the same every step). Collective.
    virtual void
    step(const StepData &data, std::vector<IO::Column> &row)
    {
      (void)data;
      (void)row;
    }

    /// At the end of a beat (or of the run), after its last step(): append
    /// /summary columns. @p activation_times: per point, the activation
    /// time in the beat [ms] (NaN where not activated; null without
    /// activation). Collective.
    virtual void
    end_beat(const StepData                         &data,
             const std::vector<std::vector<double>> *activation_times,
             std::vector<IO::Column>                &row)
    {
      (void)data;
      (void)activation_times;
      (void)row;
    }

    /// What the next step() and end_beat() depend on (reference values,
    /// the peaks of the beat so far), as numbers: for checkpoints. Called
    /// on every rank (it may be collective); the checkpoint keeps rank 0's
    /// numbers and gives them to set_state() on every rank. The default: no
    /// state.
    virtual std::vector<double>
    state() const
    {
      return {};
    }

    /// Restore what state() returned.
    virtual void
    set_state(const std::vector<double> &values)
    {
      (void)values;
    }
  };
} // namespace systole::Postprocess
