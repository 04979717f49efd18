#pragma once

#include <deal.II/base/parameter_handler.h>

#include "electrophysiology/ionic_model.h"
#include "electrophysiology/parameters.h"
#include "electrophysiology/stimulus.h"

#include <functional>
#include <memory>
#include <vector>

namespace systole::Electrophysiology
{
  /// One cell of an ionic model, paced by a stimulus current, integrated
  /// with the monodomain's time scheme without the diffusion: the ARK IMEX
  /// method of ImexIntegrator (its implicit part empty, so the explicit
  /// table of the pair), fixed steps of at most the time step that end at
  /// every stimulus switching time, and the Rush-Larsen update of the
  /// model's gates after every step (as Monodomain does). So a single cell
  /// verifies the ionic model and the time scheme that the tissue uses.
  ///
  /// Every rank integrates its own copy (MPI_COMM_SELF): the values are
  /// equal on all ranks.
  class SingleCell
  {
  public:
    /// Subsection "Cell": the pacing protocol of the "cell" problem.
    struct Pacing
    {
      double start     = 10;   ///< first stimulus onset [ms]
      double duration  = 1;    ///< [ms]
      double amplitude = 52;   ///< depolarising current [µA/µF = pA/pF]
      double period    = 1000; ///< cycle length [ms]; 0: one stimulus
      /// Fixed fibre stretch of a calcium-driven tension model (Active
      /// tension / Model = Land) [-].
      double stretch = 1;

      /// Declares subsection "Cell".
      static void
      declare(dealii::ParameterHandler &prm);

      /// Reads and validates subsection "Cell".
      static Pacing
      parse(const dealii::ParameterHandler &prm);
    };

    /// Time integration (the entries of subsection Electrophysiology; a
    /// Parameters serves as it is).
    using Settings = TimeSteps;

    /// Called after every step with the time [ms], the potential [model
    /// units] and the states.
    using Observer =
      std::function<void(const double t, const double v, const double *state)>;

    /// At @p t0 in the model's resting state.
    SingleCell(const IonicModel &model,
               const Settings   &settings,
               const Pacing     &pacing,
               const double      t0);
    ~SingleCell();

    /// Integrate to @p t_end, calling @p observer (if set) after every step.
    void
    advance(const double t_end, const Observer &observer = Observer());

    /// Current time [ms].
    double
    time() const;

    /// Potential [model units] and states at the current time.
    double
    potential() const;
    const std::vector<double> &
    state() const;

    /// ARKode steps since construction.
    unsigned long
    n_steps() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace systole::Electrophysiology
