#pragma once

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include "fibres/fibre_field.h"
#include "io/results_file.h"
#include "simulation/mechanics_model.h"
#include "simulation/unloading_parameters.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace systole
{
  class Logger;
  struct MechanicsModel;
  struct RunParameters;

  /// One iteration of the backward-displacement fixed point.
  struct UnloadingIteration
  {
    unsigned int iteration        = 0;
    double       reload_error     = 0; ///< max |X + u(X) - x_img| [mm]
    double       reference_error  = 0; ///< max |X - truth| [mm] (if known)
    double       reference_volume = 0; ///< [mm^3]
    double       reloaded_volume  = 0; ///< [mm^3]
    double       relaxation       = 0; ///< omega of the update (0: none)
    SolveCounts  forward;
  };

  /// The result of ReferenceUnloader::unload().
  struct UnloadingResult
  {
    unsigned int       iterations     = 0; ///< reference updates
    unsigned int       forward_solves = 0;
    SolveCounts        totals;
    UnloadingIteration last; ///< the final (accepted) iteration
  };

  /// The backward-displacement fixed point of Problem = unloading (Sellier
  /// 2011; Bols et al. 2013) on the mesh of a MechanicsModel, shared by
  /// Problem = unloading and Problem = calibration (Calibration / Reference
  /// = unloaded). The reference is the mesh's vertices: the constructor
  /// drops the manifolds (a moved vertex must not snap back to the
  /// generator's ellipsoid) and builds the mechanics anew on the flat cells.
  /// After every move of the vertices the mechanics (model.problem) is built
  /// anew, with the rule-based fibres of the moved geometry, on the passive
  /// law model.passive (which the caller may change between calls).
  class ReferenceUnloader
  {
  public:
    ReferenceUnloader(MechanicsModel           &model,
                      const RunParameters      &run,
                      const Fibres::Parameters &fibres,
                      Logger                   &logger,
                      const MPI_Comm            comm);
    ~ReferenceUnloader();

    /// The current reference: the mesh's vertices, one table on every rank
    /// sorted by position (partition-independent) [mm].
    const std::vector<dealii::Point<3>> &
    vertices() const;

    /// Move the mesh's vertices to @p X (same order as vertices()) and build
    /// the mechanics anew on it. Collective.
    void
    set_vertices(const std::vector<dealii::Point<3>> &X);

    /// Ramp the pressure from 0 to @p pressure [kPa] on the current
    /// reference (from zero displacement), as Problem = mechanics does:
    /// first increment 1 / Load steps, the predictor, increments adapted to
    /// the Newton iterations, a failed step halved up to Maximum step cuts
    /// times (then ExcMessage).
    SolveCounts
    inflate(const double pressure);

    /// The displacement of the last solve at every vertex of vertices().
    std::vector<dealii::Tensor<1, 3>>
    displacements() const;

    /// The fixed point X_{k+1} = X_k + omega_k (x_img - X_k - u(X_k)) from
    /// the current reference X_0, loaded to the image pressure of @p up,
    /// until the reload error max |X + u - x_img| is at most its tolerance
    /// [mm]; omega_k = 1 or Aitken's relaxation. @p truth: the true
    /// reference, if known (reference_error). Calls @p on_iteration after
    /// each forward solve. Throws after its maximum iterations updates. On
    /// return the mechanics holds the reload of the returned reference.
    UnloadingResult
    unload(const std::vector<dealii::Point<3>>                   &image,
           const UnloadingParameters                             &up,
           const std::vector<dealii::Point<3>>                   *truth,
           const std::function<void(const UnloadingIteration &)> &on_iteration);

    /// Adds the timer sections of the mechanics built before the current one
    /// to the matching "timer: ..." columns of @p statistics.
    void
    add_earlier_timings(std::vector<IO::Column> &statistics) const;

  private:
    void
    rebuild();

    class VertexTable;

    MechanicsModel               &model;
    const RunParameters          &run;
    Fibres::Parameters            fibres;
    Logger                       &logger;
    MPI_Comm                      comm;
    std::unique_ptr<VertexTable>  table;
    std::map<std::string, double> earlier_timings;
  };
} // namespace systole
