#pragma once

// Internal to src/mechanics: the state of Mechanics::Problem, shared by its
// translation units (problem.cc, assembly.cc). Not included elsewhere.

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q_cache.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include "base/linear_algebra.h"
#include "base/logger.h"
#include "mechanics/cavity_volume.h"
#include "mechanics/linear_solver.h"
#include "mechanics/problem.h"

#include <optional>
#include <set>

namespace systole::Mechanics
{
  struct Problem::Impl
  {
    Impl(const Parameters                                   &params,
         dealii::parallel::distributed::Triangulation<3, 3> &tria,
         const Geometry::BoundaryNames                      &names,
         const unsigned int                                  degree,
         const unsigned int                                  mapping_degree,
         const Materials::PassiveLaw                        &passive_law,
         const Materials::VolumetricLaw                     &volumetric_law,
         Logger                                             &logger);

    /// Residual (and, if @p with_matrix, tangent) at the current u for the
    /// given loads. Returns the l2 norm of the constrained residual. Throws
    /// ExcInvertedElement collectively when J <= 0 somewhere.
    /// If @p with_volume_derivative, also assembles dV/du of the cavity into
    /// volume_derivative (condensed like the residual).
    double
    assemble(const double pressure,
             const double active_tension,
             const bool   with_matrix,
             const bool   with_volume_derivative = false);

    /// Newton's method for R(u; p) = 0 at fixed @p pressure, or, with a
    /// @p target_volume, for (u, p) with the cavity volume constraint (p is
    /// then the Lagrange multiplier, updated in place).
    NewtonReport
    newton(double       &pressure,
           const double  active_tension,
           const double *target_volume);

    /// Cavity volume at the current u.
    double
    cavity_volume_now() const;

    /// Relative tolerance on the cavity volume of a volume-constrained solve.
    static constexpr double volume_tolerance = 2e-9;

    /// Solve tangent x = b (the tangent as last assembled) and distribute
    /// the constraints; wraps linear solver failures as Newton failures.
    unsigned int
    linear_solve(LA::MPI::Vector       &x,
                 const LA::MPI::Vector &b,
                 const unsigned int     iteration,
                 const double           relative);

    Parameters                                          params;
    dealii::parallel::distributed::Triangulation<3, 3> &tria;
    MPI_Comm                                            comm;
    Logger                                             &logger;
    const Materials::PassiveLaw                        &passive_law;
    const Materials::VolumetricLaw                     &volumetric_law;

    dealii::FESystem<3> fe;
    /// The curved geometry: MappingQ of the manifolds, its support points
    /// computed once (the manifold evaluations would otherwise dominate
    /// every assembly).
    dealii::MappingQCache<3> mapping;
    dealii::DoFHandler<3>    dof_handler;
    unsigned int             n_q_1d; ///< Gauss points per direction (cells)
    unsigned int n_q_face_1d;        ///< Gauss points per direction (faces)
    bool         reduced_volumetric; ///< volumetric term with n_q_1d - 1 points

    dealii::IndexSet                  owned, relevant;
    dealii::AffineConstraints<double> constraints; ///< homogeneous

    std::set<dealii::types::boundary_id>      fixed_ids, sliding_ids, robin_ids;
    std::optional<dealii::types::boundary_id> pressure_id;
    std::optional<CavityVolume>               cavity;

    /// Fibre frames per locally owned cell (active_cell_index) and point.
    std::vector<std::vector<Fibres::FibreBasis>> fibre_bases;
    /// Reference positions of those points.
    std::vector<std::vector<dealii::Point<3>>> quadrature_points;
    /// Active tension per locally owned cell and point [kPa], added to the
    /// uniform one (empty: none).
    std::vector<std::vector<double>> active_tension_field;

    LA::MPI::SparseMatrix tangent;
    LA::MPI::Vector       residual;          ///< owned
    LA::MPI::Vector       volume_derivative; ///< owned: dV/du, condensed
    LA::MPI::Vector       u_owned;           ///< owned
    LA::MPI::Vector       u;                 ///< ghosted copy of u_owned
    LA::MPI::Vector       u_saved;           ///< owned
    LA::MPI::Vector       u_previous; ///< owned, the save() before u_saved
    unsigned int          n_saves = 0;

    std::unique_ptr<LinearSolver> linear_solver;

    /// The linear solver holds a factorization of the bordered system of an
    /// earlier Newton iteration: the tangent, b0 = dV/du and w0 = K^-1 b0
    /// of that iterate (for the chord iterations of solve_volume()).
    bool            have_factorization = false;
    LA::MPI::Vector factorized_volume_derivative, factorized_w;
  };
} // namespace systole::Mechanics
