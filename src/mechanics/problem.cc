#include "mechanics/problem.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/errors.h"
#include "geometry/mesh.h"
#include "geometry/mesh_checks.h"
#include "materials/passive_law.h"
#include "materials/volumetric_law.h"
#include "mechanics/matrix_free_mixed_solver.h"
#include "mechanics/matrix_free_solver.h"
#include "mechanics/matrix_free_tangent.h"
#include "mechanics/problem_impl.h"

#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>

namespace systole::Mechanics
{
  namespace
  {
    /// Where a tapered support's height is measured from (collective): the
    /// best-fit plane of the base and the vertex of part @p id farthest from
    /// it, the apex.
    void
    locate_taper(const dealii::Triangulation<3, 3> &tria,
                 const Geometry::BoundaryNames     &names,
                 const dealii::types::boundary_id   id,
                 RobinSupport                      &support)
    {
      AssertThrow(names.has("base"),
                  dealii::ExcMessage(
                    "Mechanics / Robin supports: the taper of '" +
                    support.boundary +
                    "' runs from the apex to the base, "
                    "but " +
                    names.source() +
                    " has no boundary part 'base': name the base part, or "
                    "drop the taper."));
      // The fit only (a ruled base is not planar).
      const Geometry::Plane base =
        Geometry::boundary_plane(tria, names.id("base"), "base", 1.0);
      double below = 0.0, above = 0.0;
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && face->boundary_id() == id)
              for (const unsigned int v : face->vertex_indices())
                {
                  const double d = (face->vertex(v) - base.point) * base.normal;
                  below          = std::min(below, d);
                  above          = std::max(above, d);
                }
      const MPI_Comm comm   = tria.get_communicator();
      below                 = dealii::Utilities::MPI::min(below, comm);
      above                 = dealii::Utilities::MPI::max(above, comm);
      const bool apex_below = -below >= above;
      support.base_point    = base.point;
      support.apex_to_base  = apex_below ? base.normal : -base.normal;
      support.height        = apex_below ? -below : above;
      AssertThrow(support.height > 0.0,
                  dealii::ExcMessage("Mechanics / Robin supports: part '" +
                                     support.boundary +
                                     "' lies in the base plane: it has no "
                                     "apex for the taper."));
    }
  } // namespace

  MaterialLaws::MaterialLaws(const Parameters               &params,
                             const Materials::PassiveLaw    &passive_law,
                             const Materials::VolumetricLaw &volumetric_law)
    : isochoric_law(
        params.mixed()
          ? std::optional<Materials::IsochoricPart>(std::in_place, passive_law)
          : std::nullopt)
    , passive_law(isochoric_law ? *isochoric_law : passive_law)
    , volumetric_law(volumetric_law)
  {
    if (params.incompressibility == Incompressibility::nearly_incompressible)
      {
        const double kappa = volumetric_law.bulk_modulus();
        AssertThrow(kappa > 0.0,
                    dealii::ExcMessage(
                      "Material / Incompressibility = nearly incompressible "
                      "needs Material / Volumetric / Bulk modulus > 0 (it is " +
                      dealii::Utilities::to_string(kappa) +
                      " kPa); for J = 1 exactly choose incompressible."));
        inverse_bulk_modulus = 1.0 / kappa;
      }
    // Shear stiffness of the law in the reference state (the floor of the
    // Schur preconditioner's local stiffness).
    Materials::PassiveInput  in;
    Materials::PassiveOutput out;
    in.F       = dealii::unit_symmetric_tensor<3>();
    in.basis.f = dealii::Tensor<1, 3>({1, 0, 0});
    in.basis.s = dealii::Tensor<1, 3>({0, 1, 0});
    in.basis.n = dealii::Tensor<1, 3>({0, 0, 1});
    passive_law.evaluate(in, out);
    reference_shear_stiffness =
      (out.dS_dE[0][1][0][1] + out.dS_dE[0][2][0][2] + out.dS_dE[1][2][1][2]) /
      3.0;
    AssertThrow(reference_shear_stiffness > 0.0,
                dealii::ExcMessage("The passive law " + passive_law.name() +
                                   " has no shear stiffness at F = I: check "
                                   "its parameters."));
    reference_shear_stiffness *= 0.1;
  }

  Discretization::Discretization(
    const Parameters                                     &params,
    dealii::parallel::DistributedTriangulationBase<3, 3> &tria,
    const unsigned int                                    degree,
    const unsigned int                                    mapping_degree)
    : layout(degree, params, Geometry::CellKind(tria))
    , fe(layout.make_fe())
    , mapping_storage(layout.cell_kind().mapping(tria, mapping_degree))
    , mapping(*mapping_storage)
    , dof_handler(tria)
    , n_q_1d(degree + 1)
    // The cavity volume, the pressure load and their derivatives are
    // polynomials of degree 3p - 1 per face coordinate (p the larger of the
    // two degrees): p + 1 Gauss points integrate them exactly for p <= 2.
    , n_q_face_1d(
        std::max(degree, layout.cell_kind().mapping_degree(mapping_degree)) + 1)
    , reduced_volumetric(params.reduced_volumetric_integration && degree > 1)
  {}

  Problem::Impl::Impl(const Inputs &in)
    : params(in.params)
    , tria(in.tria)
    , comm(in.tria.get_communicator())
    , logger(in.logger)
    , material(in.params, in.passive_law, in.volumetric_law)
    , discretization(in.params, in.tria, in.degree, in.mapping_degree)
    , boundaries(in.params, in.tria, in.names)
    , loads(in.params, in.tria, boundaries, in.logger)
    , timer(timer_sink,
            dealii::TimerOutput::never,
            dealii::TimerOutput::wall_times)
  {}

  namespace
  {
    /// The boundary ids of the parts @p parts (Mechanics / @p entry): each
    /// named part must exist and carry faces.
    std::set<dealii::types::boundary_id>
    boundary_ids(const dealii::Triangulation<3, 3> &tria,
                 const Geometry::BoundaryNames     &names,
                 const std::vector<std::string>    &parts,
                 const std::string                 &entry)
    {
      std::set<dealii::types::boundary_id> result;
      for (const auto &part : parts)
        {
          std::string known;
          for (const auto &name : names.names())
            known += (known.empty() ? "" : ", ") + name;
          if (!names.has(part))
            AssertThrow(false,
                        dealii::ExcMessage(
                          "Mechanics / " + entry + " names boundary part '" +
                          part + "': " + names.source() +
                          " has no such part (it has: " + known + ")."));
          Geometry::require_boundary(tria, names, part);
          result.insert(names.id(part));
        }
      return result;
    }

    /// The linear solver of @p n_dofs DoFs: "direct" or "iterative" (Linear
    /// solver = auto resolved).
    std::string
    resolve_linear_solver(const Parameters                     &params,
                          const dealii::types::global_dof_index n_dofs,
                          const bool                            matrix_free)
    {
      if (params.linear_solver != "auto")
        return params.linear_solver;
      if (n_dofs <= params.direct_solver_limit)
        return "direct";
      return matrix_free ? "matrix-free" : "iterative";
    }

    /// Whether the tangent is symmetric: when every load derives from a
    /// potential: the hyperelastic energy, the springs, and the pressures on
    /// cavities (each load is the exact derivative of the discrete cavity
    /// volume while the rim stays in the base plane, so its tangent is a
    /// Hessian). A follower pressure on an open surface is not.
    bool
    symmetric_tangent(const Parameters              &params,
                      const Geometry::BoundaryNames &names,
                      const BoundaryConditions      &boundaries,
                      const CavityLoads             &loads)
    {
      // A cavity's load is that derivative only while its rim stays in the
      // base plane: the base must be held in it (fixed or sliding). The
      // viscous stress of a time step, eta dE/dt with E(F) and its rate, has
      // a tangent that is not symmetric.
      // A rim-fan cavity (CavityVolume::Closure::rim_fan) is closed by a lid
      // that moves with its rim: the load (the endocardial flux) is dV/du
      // only while the rim does not move at all, a fixed base.
      bool fan = false;
      for (const auto &cavity : loads.cavities)
        fan = fan || cavity.closure() == CavityVolume::Closure::rim_fan;
      const bool base_held =
        !names.has("base") ||
        boundaries.fixed_ids.count(names.id("base")) > 0 ||
        (!fan && boundaries.sliding_ids.count(names.id("base")) > 0);
      // With the pressure on the moving lids the load is p dV/du again (its
      // assembled tangent omits the rim's low-rank coupling, and is
      // symmetric).
      return (loads.pressure_ids.empty() ||
              (!loads.cavities.empty() &&
               (base_held || params.lid_pressure))) &&
             params.viscosity == 0.0;
    }

    /// The augmented Lagrangian (Mechanics / Augmented Lagrangian factor):
    /// checks the factor and sets up the pattern of G, which couples the
    /// displacement DoFs of a cell to its (discontinuous) pressure DoFs.
    /// Throws unless the Augmented Lagrangian factor gamma is below (kappa
    /// + mu) / mu.
    void
    check_augmented_lagrangian(const Parameters   &params,
                               const MaterialLaws &material)
    {
      const double mu = 10.0 * material.reference_shear_stiffness;
      AssertThrow(
        material.inverse_bulk_modulus * params.augmented_lagrangian * mu <
          1.0 + material.inverse_bulk_modulus * mu,
        dealii::ExcMessage(
          "Mechanics / Augmented Lagrangian factor (" +
          dealii::Utilities::to_string(params.augmented_lagrangian) +
          ") must be below (kappa + mu) / mu = " +
          dealii::Utilities::to_string(
            1.0 / (material.inverse_bulk_modulus * mu) + 1.0) +
          " (Material / Volumetric / Bulk modulus against the law's shear "
          "stiffness): lower it, or set it to 0."));
    }

    void
    setup_augmentation(const Parameters     &params,
                       const MaterialLaws   &material,
                       const Discretization &discretization,
                       const MPI_Comm        comm,
                       LinearSystem         &system)
    {
      check_augmented_lagrangian(params, material);
      system.augmented_lagrangian = params.augmented_lagrangian;
      dealii::DynamicSparsityPattern coupling_pattern(discretization.relevant);
      const auto                    &fe = *discretization.fe;
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell()),
        u_dofs, p_dofs;
      for (const auto &cell :
           discretization.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            cell->get_dof_indices(dofs);
            u_dofs.clear();
            p_dofs.clear();
            for (unsigned int i = 0; i < dofs.size(); ++i)
              (fe.system_to_component_index(i).first < 3 ? u_dofs : p_dofs)
                .push_back(dofs[i]);
            discretization.constraints.add_entries_local_to_global(
              u_dofs,
              p_dofs,
              coupling_pattern,
              false);
          }
      dealii::SparsityTools::distribute_sparsity_pattern(
        coupling_pattern,
        discretization.owned,
        comm,
        discretization.relevant);
      system.augmentation = std::make_unique<LA::MPI::SparseMatrix>();
      system.augmentation->reinit(discretization.owned,
                                  discretization.owned,
                                  coupling_pattern,
                                  comm);
    }
  } // namespace

  BoundaryConditions::BoundaryConditions(
    const Parameters                  &params,
    const dealii::Triangulation<3, 3> &tria,
    const Geometry::BoundaryNames     &names)
    : boundary_names(names)
  {
    fixed_ids =
      boundary_ids(tria, names, params.fixed_boundaries, "Fixed boundaries");
    sliding_ids = boundary_ids(tria,
                               names,
                               params.sliding_boundaries,
                               "Sliding boundaries");
    for (const auto &support : params.all_robin_supports())
      {
        const auto id = *boundary_ids(tria,
                                      names,
                                      {support.boundary},
                                      "Robin boundaries (or Robin supports)")
                           .begin();
        robin_supports[id] = support;
        if (support.from_end_diastole)
          release.time = support.release_time;
        if (support.tapered())
          locate_taper(tria, names, id, robin_supports[id]);
      }
  }

  bool
  BoundaryConditions::any_from_end_diastole() const
  {
    return std::any_of(robin_supports.begin(),
                       robin_supports.end(),
                       [](const auto &s) {
                         return s.second.from_end_diastole;
                       });
  }

  void
  BoundaryConditions::support_stretch(
    const dealii::FEFaceValues<3>            &fe_face,
    const dealii::FEValuesExtractors::Vector &displacement,
    const LA::MPI::Vector                    &u,
    const RobinSupport                       &support,
    std::vector<dealii::Tensor<1, 3>>        &values,
    std::vector<dealii::Tensor<1, 3>>        &scratch) const
  {
    values.resize(fe_face.n_quadrature_points);
    fe_face[displacement].get_function_values(u, values);
    if (!support.from_end_diastole)
      return;
    scratch.resize(fe_face.n_quadrature_points);
    fe_face[displacement].get_function_values(support_reference, scratch);
    for (unsigned int q = 0; q < values.size(); ++q)
      values[q] -= scratch[q];
  }

  CavityLoads::CavityLoads(const Parameters                  &params,
                           const dealii::Triangulation<3, 3> &tria,
                           const BoundaryConditions          &boundaries,
                           Logger                            &logger)
    : pressure_names(params.pressure_boundaries())
  {
    // Pressure parts, each with its own pressure; with a base, each is a
    // cavity closed by the base plane.
    const Geometry::BoundaryNames &names = boundaries.boundary_names;
    for (const auto &part : pressure_names)
      {
        const auto id =
          *boundary_ids(tria, names, {part}, "Pressure boundary").begin();
        AssertThrow(
          std::find(pressure_ids.begin(), pressure_ids.end(), id) ==
            pressure_ids.end(),
          dealii::ExcMessage(
            "Mechanics / Pressure boundary lists the boundary part '" + part +
            "' twice (or two names of one boundary id): list each "
            "part once."));
        pressure_ids.push_back(id);
      }
    if (!pressure_ids.empty() && names.has("base"))
      close_cavities(tria, boundaries, logger);
  }

  void
  CavityLoads::close_cavities(const dealii::Triangulation<3, 3> &tria,
                              const BoundaryConditions          &boundaries,
                              Logger                            &logger)
  {
    const Geometry::BoundaryNames &names = boundaries.boundary_names;
    Geometry::require_boundary(tria, names, "base");
    // The base plane; for a ruled base, each cavity's basal ring if it is
    // planar, else the fan over the ring (a patient base, a warped cut),
    // with a warning when it is far from a plane. A base that is not held in
    // its plane (springs, free) moves the rim out of it: the fan over the
    // moving rim closes every cavity then.
    const auto base_id       = names.id("base");
    const bool base_in_plane = boundaries.fixed_ids.count(base_id) > 0 ||
                               boundaries.sliding_ids.count(base_id) > 0;
    if (!base_in_plane)
      logger.line("The base is not held in its plane: each cavity is closed "
                  "by the fan\n  from its moving rim's vertex mean.");
    for (unsigned int c = 0; c < pressure_ids.size(); ++c)
      {
        Geometry::check_cavity_rim(tria, names, pressure_names[c], "base");
        const auto closure =
          Geometry::cavity_closure(tria, names, pressure_names[c]);
        moving_lid.push_back(!base_in_plane);
        if (!base_in_plane)
          {
            cavities.emplace_back(tria, pressure_ids[c], base_id);
            continue;
          }
        if (closure.plane)
          {
            cavities.emplace_back(pressure_ids[c], *closure.plane);
            continue;
          }
        if (closure.off_plane >
            Geometry::rim_warning_fraction * closure.rim_size)
          {
            std::ostringstream line;
            line << std::setprecision(3) << "Warning: the rim of cavity '"
                 << pressure_names[c] << "' lies up to " << closure.off_plane
                 << " mm off its best plane ("
                 << 100.0 * closure.off_plane / closure.rim_size << " % of its "
                 << closure.rim_size
                 << " mm size); its volume is closed by the fan from the "
                    "rim's vertex mean.";
            logger.line(line.str());
          }
        cavities.emplace_back(tria, pressure_ids[c], base_id);
      }
  }

  void
  Discretization::make_constraints(
    const dealii::DoFHandler<3>       &dofs,
    const BoundaryConditions          &boundaries,
    dealii::AffineConstraints<double> &result) const
  {
    // Zero displacement on fixed parts, zero normal displacement on sliding
    // ones (the Newton updates are homogeneous too); the displacement is
    // components 0-2.
    dealii::IndexSet dofs_relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dofs, dofs_relevant);
    result.clear();
    result.reinit(dofs_relevant);
    dealii::DoFTools::make_hanging_node_constraints(dofs, result);
    const unsigned int n_components = dofs.get_fe().n_components();
    const dealii::FEValuesExtractors::Vector displacement(0);
    for (const auto id : boundaries.fixed_ids)
      dealii::VectorTools::interpolate_boundary_values(
        mapping,
        dofs,
        id,
        dealii::Functions::ZeroFunction<3>(n_components),
        result,
        dofs.get_fe().component_mask(displacement));
    if (!boundaries.sliding_ids.empty())
      dealii::VectorTools::compute_no_normal_flux_constraints(
        dofs,
        0,
        boundaries.sliding_ids,
        result,
        mapping);
    result.close();
  }

  void
  Discretization::distribute_dofs(const BoundaryConditions &boundaries)
  {
    dof_handler.distribute_dofs(*fe);
    layout.renumber(dof_handler);
    owned = dof_handler.locally_owned_dofs();
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    make_constraints(dof_handler, boundaries, constraints);
  }

  void
  Discretization::measure(const MPI_Comm comm)
  {
    const dealii::Quadrature<3> rule = cell_quadrature(n_q_1d);
    dealii::FEValues<3> fe_jxw(mapping, *fe, rule, dealii::update_JxW_values);
    double              volume = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_jxw.reinit(cell);
          for (const unsigned int q : fe_jxw.quadrature_point_indices())
            volume += fe_jxw.JxW(q);
        }
    body_volume = dealii::Utilities::MPI::sum(volume, comm);
    n_pressure_dofs =
      dealii::Utilities::MPI::sum(static_cast<long>(
                                    layout.owned(1).n_elements()),
                                  comm);
  }

  void
  QuadraturePoints::initialize(const Discretization &discretization,
                               const FibreFunction  &fibres)
  {
    // Fibre frames at the quadrature points of the locally owned cells.
    const dealii::Quadrature<3> quadrature =
      discretization.cell_quadrature(discretization.n_q_1d);
    dealii::FEValues<3>             fe_values(discretization.mapping,
                                  *discretization.fe,
                                  quadrature,
                                  dealii::update_quadrature_points);
    std::vector<Fibres::FibreBasis> bases;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fibres(cell, fe_values.get_quadrature_points(), bases);
          point_data.initialize(cell, quadrature.size());
          const auto data = point_data.get_data(cell);
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              data[q]->basis    = bases[q];
              data[q]->position = fe_values.quadrature_point(q);
            }
        }
  }

  void
  Problem::Impl::reinit_system(const bool sparse_tangent)
  {
    const Discretization &d = discretization;
    if (sparse_tangent)
      {
        dealii::DynamicSparsityPattern dsp(d.relevant);
        dealii::DoFTools::make_sparsity_pattern(d.dof_handler,
                                                dsp,
                                                d.constraints,
                                                false);
        dealii::SparsityTools::distribute_sparsity_pattern(dsp,
                                                           d.owned,
                                                           comm,
                                                           d.relevant);
        system.tangent.reinit(d.owned, d.owned, dsp, comm);
      }
    system.residual.reinit(d.owned, comm);
    loads.volume_derivatives.resize(loads.cavities.size());
    for (auto &b : loads.volume_derivatives)
      b.reinit(d.owned, comm);
    u_owned.reinit(d.owned, comm);
    history.u_saved.reinit(d.owned, comm);
    history.u_previous.reinit(d.owned, comm);
    history.u_before.reinit(d.owned, comm);
    factorized.u.reinit(d.owned, comm);
    u.reinit(d.owned, d.relevant, comm);
    if (boundaries.any_from_end_diastole())
      {
        boundaries.support_reference.reinit(d.owned, d.relevant, comm);
        boundaries.release.from.reinit(d.owned, comm);
        boundaries.release.to.reinit(d.owned, comm);
      }
  }

  Problem::Problem(const Inputs &in)
    : impl(std::make_unique<Impl>(in))
  {
    const Parameters &params = in.params;
    Impl             &m      = *impl;
    m.discretization.distribute_dofs(m.boundaries);
    const auto        n_dofs = m.discretization.dof_handler.n_dofs();
    const std::string solver =
      resolve_linear_solver(params,
                            n_dofs,
                            in.fixed_pressures && m.matrix_free_applies());
    // (The matrix-free solvers have no sparse tangent at all.)
    m.reinit_system(solver != "matrix-free");
    m.points.initialize(m.discretization, in.fibres);
    m.discretization.measure(m.comm);

    // Accelerated chords pay where factorizations dominate the cost.
    if (params.chord_acceleration_auto)
      m.params.chord_acceleration_depth =
        solver == "direct" && n_dofs >= Parameters::auto_acceleration_dofs
          ? Parameters::auto_acceleration_depth
          : 0;
    m.system.linear_solver_name = solver;
    m.create_linear_solver(
      symmetric_tangent(params, in.names, m.boundaries, m.loads));
    if (m.system.linear_solver->needs_pressure_matrix())
      m.system.pressure_matrix = std::make_unique<PressureMatrix>(
        m.discretization.layout,
        m.comm,
        params.pressure_element == PressureElement::discontinuous
          ? m.discretization.fe->base_element(1).n_dofs_per_cell()
          : 64);
    if (m.system.pressure_matrix != nullptr &&
        params.pressure_element == PressureElement::discontinuous &&
        params.augmented_lagrangian > 0.0)
      setup_augmentation(params,
                         m.material,
                         m.discretization,
                         m.comm,
                         m.system);
  }

  void
  Problem::Impl::tangent_vmult(LA::MPI::Vector       &dst,
                               const LA::MPI::Vector &src) const
  {
    if (MatrixFreeMixedSolver *mixed =
          system.linear_solver->matrix_free_mixed())
      mixed->vmult(dst, src);
    else if (MatrixFreeTangent *tangent =
               system.linear_solver->matrix_free_tangent())
      {
        MatrixFreeTangent::Vector x, y;
        tangent->initialize_dof_vector(x);
        tangent->initialize_dof_vector(y);
        copy_owned(src, x);
        tangent->vmult(y, x);
        copy_owned(y, dst);
        dst.compress(dealii::VectorOperation::insert);
      }
    else
      system.tangent.vmult(dst, src);
    if (system.augmentation != nullptr)
      {
        LA::MPI::Vector correction(discretization.owned, comm);
        system.augmentation->vmult(correction, dst);
        dst -= correction;
      }
    for (unsigned int j = 0; j < loads.low_rank_u.size(); ++j)
      dst.add(loads.low_rank_v[j] * src, loads.low_rank_u[j]);
  }

  void
  Problem::Impl::factorize_low_rank()
  {
    factorized.low_rank_v.clear();
    factorized.low_rank_z.clear();
    const unsigned int r = loads.low_rank_u.size();
    if (r == 0)
      return;
    std::vector<LA::MPI::Vector> z(r);
    for (unsigned int j = 0; j < r; ++j)
      {
        z[j].reinit(discretization.owned, comm);
        system.linear_solver->solve(z[j], loads.low_rank_u[j]);
        discretization.constraints.distribute(z[j]);
      }
    dealii::FullMatrix<double> small(r, r);
    for (unsigned int i = 0; i < r; ++i)
      for (unsigned int j = 0; j < r; ++j)
        small(i, j) = (i == j ? 1.0 : 0.0) + loads.low_rank_v[i] * z[j];
    factorized.low_rank_inverse.reinit(r, r);
    factorized.low_rank_inverse.invert(small);
    factorized.low_rank_v = loads.low_rank_v;
    factorized.low_rank_z = std::move(z);
  }

  Problem::~Problem() = default;

  unsigned int
  Problem::Impl::linear_solve(LA::MPI::Vector       &x,
                              const LA::MPI::Vector &b,
                              const unsigned int     iteration,
                              const double           relative,
                              const double           tolerance)
  {
    try
      {
        x = 0;
        if (tolerance > 0.0)
          system.linear_solver->set_tolerance(tolerance);
        const unsigned int its = system.linear_solver->solve(x, b);
        system.linear_solver->set_tolerance(params.linear_tolerance);
        discretization.constraints.distribute(x);
        // (K + U V^T)^-1 b = x - Z (I + V^T Z)^-1 V^T x (Woodbury).
        const unsigned int r = factorized.low_rank_v.size();
        if (r > 0)
          {
            dealii::Vector<double> y(r), s(r);
            for (unsigned int j = 0; j < r; ++j)
              y[j] = factorized.low_rank_v[j] * x;
            factorized.low_rank_inverse.vmult(s, y);
            for (unsigned int j = 0; j < r; ++j)
              x.add(-s[j], factorized.low_rank_z[j]);
          }
        return its;
      }
    catch (const dealii::ExceptionBase &e)
      {
        system.linear_solver->set_tolerance(params.linear_tolerance);
        throw_linear_solver_failure(e, iteration, relative);
      }
    return 0;
  }

  void
  throw_linear_solver_failure(const dealii::ExceptionBase &e,
                              const unsigned int           iteration,
                              const double                 relative)
  {
    AssertThrow(false,
                ExcNewtonDidNotConverge(std::string("linear solver: ") +
                                          one_line_message(e),
                                        iteration,
                                        relative));
  }

  dealii::Vector<double>
  Problem::Impl::uniform_pressures(const double pressure) const
  {
    dealii::Vector<double> pressures(loads.pressure_ids.size());
    pressures = pressure;
    return pressures;
  }

  NewtonReport
  Problem::solve(const double pressure, const double active_tension)
  {
    dealii::Vector<double> p = impl->uniform_pressures(pressure);
    return impl->newton(p, active_tension, nullptr);
  }

  NewtonReport
  Problem::solve(const dealii::Vector<double> &pressures,
                 const double                  active_tension)
  {
    AssertThrow(pressures.size() == impl->loads.pressure_ids.size(),
                dealii::ExcMessage(
                  "Mechanics::Problem::solve: " +
                  std::to_string(pressures.size()) + " pressures given for " +
                  std::to_string(impl->loads.pressure_ids.size()) +
                  " pressure parts (Mechanics / Pressure boundary)."));
    dealii::Vector<double> p = pressures;
    return impl->newton(p, active_tension, nullptr);
  }

  NewtonReport
  Problem::solve_cavities(const VolumeTarget     &target,
                          const double            active_tension,
                          dealii::Vector<double> &pressures)
  {
    AssertThrow(!impl->loads.cavities.empty(),
                dealii::ExcMessage(
                  "A volume constraint needs a cavity (a Mechanics / Pressure "
                  "boundary on a mesh with a boundary part 'base')."));
    AssertThrow(pressures.size() == impl->loads.cavities.size(),
                dealii::ExcMessage(
                  "Mechanics::Problem::solve_cavities: " +
                  std::to_string(pressures.size()) + " pressures given for " +
                  std::to_string(impl->loads.cavities.size()) + " cavities."));
    AssertThrow(impl->system.linear_solver->matrix_free_tangent() == nullptr,
                dealii::ExcMessage(
                  "The matrix-free linear solver does not solve cavity-volume "
                  "constraints (the bordered Newton needs its factorization); "
                  "use Mechanics / Linear solver = iterative or direct."));
    return impl->newton(pressures, active_tension, &target);
  }

  NewtonReport
  Problem::solve_volume(const double target_volume,
                        const double active_tension,
                        double      &pressure)
  {
    AssertThrow(impl->loads.cavities.size() == 1,
                dealii::ExcMessage(
                  "solve_volume() constrains one cavity; this problem has " +
                  std::to_string(impl->loads.cavities.size()) +
                  " (use solve_cavities())."));
    dealii::Vector<double> p(1);
    p[0]              = pressure;
    const auto report = solve_cavities(
      [target_volume](const dealii::Vector<double> &,
                      dealii::Vector<double> &W,
                      dealii::FullMatrix<double> &) { W[0] = target_volume; },
      active_tension,
      p);
    pressure = p[0];
    return report;
  }

  double
  Problem::Impl::seconds_in(const std::string &section) const
  {
    const auto times =
      timer.get_summary_data(dealii::TimerOutput::total_wall_time);
    const auto it = times.find(section);
    return it == times.end() ? 0.0 : it->second;
  }

  std::array<double, 2>
  block_norms(const FieldLayout &layout, const LA::MPI::Vector &v)
  {
    // Owned entries: the displacement range comes first, then the pressure.
    const auto         n_u = layout.owned(0).n_elements();
    const auto         n   = v.locally_owned_size();
    const PetscScalar *x;
    VecGetArrayRead(v, &x);
    std::array<double, 2> squares = {{0.0, 0.0}};
    for (std::size_t i = 0; i < n; ++i)
      squares[i < n_u ? 0 : 1] += x[i] * x[i];
    VecRestoreArrayRead(v, &x);
    MPI_Allreduce(MPI_IN_PLACE,
                  squares.data(),
                  2,
                  MPI_DOUBLE,
                  MPI_SUM,
                  v.get_mpi_communicator());
    return {{std::sqrt(squares[0]), std::sqrt(squares[1])}};
  }


  void
  Problem::Impl::create_linear_solver(const bool symmetric)
  {
    system.symmetric_tangent = symmetric;
    if (system.linear_solver_name == "matrix-free")
      {
        const std::string alternative =
          " (Mechanics / Linear solver = matrix-free); use Linear solver = "
          "iterative or direct.";
        const bool mixed = discretization.layout.mixed();
        AssertThrow(discretization.fe->degree == 2 &&
                      !discretization.layout.cell_kind().simplex() &&
                      (!mixed || params.pressure_element ==
                                   PressureElement::discontinuous),
                    dealii::ExcMessage(
                      "The matrix-free linear solver needs Q2 displacements "
                      "on hexahedra, with no pressure field (the penalty "
                      "formulation) or a discontinuous P1 one (Pressure "
                      "element = discontinuous)" +
                      alternative));
        AssertThrow(boundaries.robin_supports.empty(),
                    dealii::ExcMessage("The matrix-free linear solver has no "
                                       "spring-dashpot (Robin) supports" +
                                       alternative));
        check_matrix_free_tangent(mixed);
        const MatrixFreeSolver::MakeConstraints make_constraints =
          [this](const dealii::DoFHandler<3>       &dofs,
                 dealii::AffineConstraints<double> &constraints) {
            discretization.make_constraints(dofs, boundaries, constraints);
          };
        if (mixed)
          {
            check_augmented_lagrangian(params, material);
            system.augmented_lagrangian = params.augmented_lagrangian;
            system.linear_solver = std::make_unique<MatrixFreeMixedSolver>(
              discretization.mapping,
              discretization.dof_handler,
              discretization.layout,
              make_constraints,
              params.linear_tolerance);
          }
        else
          system.linear_solver =
            std::make_unique<MatrixFreeSolver>(discretization.mapping,
                                               discretization.dof_handler,
                                               discretization.constraints,
                                               make_constraints,
                                               params.linear_tolerance,
                                               symmetric);
        factorized.held = false;
        return;
      }
    system.linear_solver =
      Mechanics::create_linear_solver({system.linear_solver_name,
                                       discretization.mapping,
                                       discretization.dof_handler,
                                       discretization.layout,
                                       discretization.constraints,
                                       params.linear_tolerance,
                                       symmetric,
                                       params.displacement_preconditioner});
    factorized.held = false;
  }

  dealii::Vector<double>
  Problem::Impl::cavity_volumes_now() const
  {
    dealii::Vector<double> volumes(loads.cavities.size());
    for (unsigned int i = 0; i < loads.cavities.size(); ++i)
      volumes[i] = loads.cavities[i].volume(discretization.mapping,
                                            discretization.dof_handler,
                                            u,
                                            discretization.n_q_face_1d);
    return volumes;
  }

  dealii::Tensor<1, 3>
  Problem::net_pressure_force(const dealii::Vector<double> &pressures)
  {
    Impl &m = *impl;
    // The load is what the pressures take from the residual (R = internal
    // forces - loads).
    m.assemble(dealii::Vector<double>(pressures.size()), 0.0, false);
    LA::MPI::Vector load = m.system.residual;
    m.assemble(pressures, 0.0, false);
    load -= m.system.residual;
    dealii::Tensor<1, 3> force;
    for (unsigned int k = 0; k < 3; ++k)
      {
        dealii::ComponentMask mask(m.discretization.fe->n_components(), false);
        mask.set(k, true);
        for (const auto i :
             dealii::DoFTools::extract_dofs(m.discretization.dof_handler, mask))
          force[k] += load(i);
      }
    return dealii::Utilities::MPI::sum(force, m.comm);
  }

  void
  Problem::quadrature_points(
    std::vector<std::vector<dealii::Point<3>>> &points) const
  {
    const Impl &m = *impl;
    points.assign(m.tria.n_active_cells(), {});
    for (const auto &cell : m.tria.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto &data : m.points.point_data.get_data(cell))
          points[cell->active_cell_index()].push_back(data->position);
  }

  void
  Problem::Impl::set_point_values(
    const std::vector<std::vector<double>> &values,
    double PointData::*value,
    const bool         allow_empty,
    const std::string &caller)
  {
    const bool empty = allow_empty && values.empty();
    AssertThrow(empty || values.size() == tria.n_active_cells(),
                dealii::ExcMessage(caller +
                                   ": one vector per cell (by active cell "
                                   "index) expected."));
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto data = points.point_data.get_data(cell);
          const auto c    = cell->active_cell_index();
          AssertThrow(empty || values[c].size() == data.size(),
                      dealii::ExcMessage(caller +
                                         ": one value per quadrature point "
                                         "expected."));
          for (unsigned int q = 0; q < data.size(); ++q)
            (*data[q]).*value = empty ? 0.0 : values[c][q];
        }
  }

  void
  Problem::set_active_tension(std::vector<std::vector<double>> tension)
  {
    impl->set_point_values(tension,
                           &PointData::tension,
                           true,
                           "set_active_tension");
  }

  void
  Problem::set_displacement(const dealii::Function<3> &displacement)
  {
    Impl &m = *impl;
    if (!m.discretization.layout.mixed())
      dealii::VectorTools::interpolate(m.discretization.mapping,
                                       m.discretization.dof_handler,
                                       displacement,
                                       m.u_owned);
    else
      {
        // The pressure element has no support points: interpolate the
        // displacement on a displacement-only space and copy it node by node
        // (same FE_Q base, same cells); the pressure becomes zero.
        const dealii::FESystem<3> fe_u(m.discretization.fe->base_element(0), 3);
        dealii::DoFHandler<3>     dof_u(m.tria);
        dof_u.distribute_dofs(fe_u);
        dealii::IndexSet relevant_u;
        dealii::DoFTools::extract_locally_relevant_dofs(dof_u, relevant_u);
        LA::MPI::Vector owned_u(dof_u.locally_owned_dofs(), m.comm);
        dealii::VectorTools::interpolate(m.discretization.mapping,
                                         dof_u,
                                         displacement,
                                         owned_u);
        LA::MPI::Vector ghosted_u(dof_u.locally_owned_dofs(),
                                  relevant_u,
                                  m.comm);
        ghosted_u = owned_u;
        m.u_owned = 0;
        std::vector<dealii::types::global_dof_index> dofs(
          m.discretization.fe->n_dofs_per_cell()),
          dofs_u(fe_u.n_dofs_per_cell());
        auto cell_u = dof_u.begin_active();
        for (const auto &cell :
             m.discretization.dof_handler.active_cell_iterators())
          {
            if (cell->is_locally_owned())
              {
                cell->get_dof_indices(dofs);
                cell_u->get_dof_indices(dofs_u);
                for (unsigned int j = 0; j < dofs_u.size(); ++j)
                  {
                    const auto i =
                      m.discretization.fe->component_to_system_index(
                        fe_u.system_to_component_index(j).first,
                        fe_u.system_to_component_index(j).second);
                    if (m.discretization.owned.is_element(dofs[i]))
                      m.u_owned(dofs[i]) = ghosted_u(dofs_u[j]);
                  }
              }
            ++cell_u;
          }
        m.u_owned.compress(dealii::VectorOperation::insert);
      }
    m.discretization.constraints.distribute(m.u_owned);
    m.u = m.u_owned;
  }

  void
  Problem::save()
  {
    // (The older states move by swapping their data, one copy in all.)
    SolutionHistory &h = impl->history;
    h.u_before.swap(h.u_previous);
    h.u_previous.swap(h.u_saved);
    h.u_saved = impl->u_owned;
    ++h.n_saves;
  }

  void
  Problem::predict(const double ratio)
  {
    if (impl->history.n_saves >= 2)
      predict({{1 + ratio, -ratio, 0}});
    else
      predict({{1, 0, 0}});
  }

  void
  Problem::predict(const std::array<double, 3> &weights)
  {
    Impl                  &m         = *impl;
    const SolutionHistory &h         = m.history;
    const LA::MPI::Vector *states[3] = {&h.u_saved, &h.u_previous, &h.u_before};
    m.u_owned                        = *states[0];
    m.u_owned *= weights[0];
    for (unsigned int i = 1; i < 3; ++i)
      if (weights[i] != 0.0)
        {
          AssertThrow(h.n_saves > i,
                      dealii::ExcInternalError("predict() from a state "
                                               "that was not saved"));
          m.u_owned.add(weights[i], *states[i]);
        }
    m.u                   = m.u_owned;
    m.history.u_predicted = m.u_owned;
  }

  double
  Problem::predictor_error() const
  {
    // The largest nodal difference over the displacement entries (in the
    // mixed formulation the pressure entries follow them; kPa, not mm).
    const Impl &m = *impl;
    if (m.history.u_predicted.size() != m.u_owned.size())
      return 0.0;
    const auto         n_u = m.discretization.layout.owned(0).n_elements();
    const PetscScalar *x, *y;
    VecGetArrayRead(m.u_owned, &x);
    VecGetArrayRead(m.history.u_predicted, &y);
    double e = 0;
    for (std::size_t i = 0; i < n_u; ++i)
      e = std::max(e, std::abs(x[i] - y[i]));
    VecRestoreArrayRead(m.u_owned, &x);
    VecRestoreArrayRead(m.history.u_predicted, &y);
    MPI_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_MAX, m.comm);
    return e;
  }

  void
  Problem::predict(const double ratio,
                   const double pressure,
                   const double active_tension)
  {
    Impl      &m        = *impl;
    const auto residual = [&]() {
      try
        {
          m.assemble(m.uniform_pressures(pressure), active_tension, false);
        }
      catch (const ExcInvertedElement &)
        {
          return std::numeric_limits<double>::infinity();
        }
      const auto norms =
        block_norms(m.discretization.layout, m.system.residual);
      return std::isfinite(norms[0]) ? norms[0]
                                     : std::numeric_limits<double>::infinity();
    };
    predict(0.0);
    const double at_saved = residual();
    predict(ratio);
    const double at_extrapolated = residual();
    const bool   keep            = at_extrapolated < at_saved;
    if (!keep)
      predict(0.0);
    m.logger.detail() << "      predictor: " << (keep ? "secant" : "last state")
                      << " (|R_u| " << std::scientific << std::setprecision(3)
                      << at_extrapolated << " extrapolated, " << at_saved
                      << " at the last state)" << std::defaultfloat
                      << std::endl;
  }

  void
  Problem::restore()
  {
    impl->u_owned = impl->history.u_saved;
    impl->u       = impl->u_owned;
  }

  unsigned int
  Problem::n_cavities() const
  {
    return impl->loads.cavities.size();
  }

  std::vector<std::string>
  Problem::cavity_names() const
  {
    return impl->loads.cavities.empty() ? std::vector<std::string>()
                                        : impl->loads.pressure_names;
  }

  dealii::Vector<double>
  Problem::cavity_volumes() const
  {
    return impl->cavity_volumes_now();
  }

  bool
  Problem::has_cavity() const
  {
    return !impl->loads.cavities.empty();
  }

  double
  Problem::cavity_volume() const
  {
    AssertThrow(impl->loads.cavities.size() == 1,
                dealii::ExcMessage(
                  "cavity_volume() is the volume of the one cavity; this "
                  "problem has " +
                  std::to_string(impl->loads.cavities.size()) +
                  " (a cavity is a Mechanics / Pressure boundary part on a "
                  "mesh with a boundary part 'base'; use cavity_volumes())."));
    return impl->cavity_volumes_now()[0];
  }

  std::vector<dealii::Point<3>>
  Problem::deformed_positions(const std::vector<dealii::Point<3>> &points) const
  {
    const Impl        &m    = *impl;
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(m.comm);
    std::vector<dealii::Point<3>> result(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        // Every rank looks for a locally owned cell that holds the point; the
        // lowest such rank reports its value.
        std::pair<dealii::DoFHandler<3>::active_cell_iterator, dealii::Point<3>>
                     found;
        unsigned int holder = dealii::numbers::invalid_unsigned_int;
        try
          {
            const auto cells =
              dealii::GridTools::find_all_active_cells_around_point(
                m.discretization.mapping,
                m.discretization.dof_handler,
                points[i],
                1e-10);
            for (const auto &c : cells)
              if (c.first->is_locally_owned())
                {
                  found  = c;
                  holder = rank;
                  break;
                }
          }
        catch (...)
          {}
        holder = dealii::Utilities::MPI::min(holder, m.comm);
        AssertThrow(holder != dealii::numbers::invalid_unsigned_int,
                    dealii::ExcMessage(
                      "Mechanics / Tracked points: the point (" +
                      dealii::Utilities::to_string(points[i][0]) + ", " +
                      dealii::Utilities::to_string(points[i][1]) + ", " +
                      dealii::Utilities::to_string(points[i][2]) +
                      ") lies outside the mesh."));
        dealii::Tensor<1, 3> value;
        if (holder == rank)
          {
            // The search tolerance lets the point lie just outside its
            // cell: pull it in (a tetrahedron's point is within 1e-10).
            const dealii::Quadrature<3> at(
              found.first->reference_cell().is_hyper_cube()
                ? dealii::GeometryInfo<3>::project_to_unit_cell(found.second)
                : found.second);
            dealii::FEValues<3> fe_values(m.discretization.mapping,
                                          *m.discretization.fe,
                                          at,
                                          dealii::update_values);
            fe_values.reinit(found.first);
            std::vector<dealii::Tensor<1, 3>> u_at(1);
            fe_values[dealii::FEValuesExtractors::Vector(0)]
              .get_function_values(m.u, u_at);
            value = u_at[0];
          }
        value     = dealii::Utilities::MPI::sum(value, m.comm);
        result[i] = points[i] + value;
      }
    return result;
  }

  void
  Problem::attach_output(dealii::DataOut<3, 3> &data_out) const
  {
    data_out.attach_dof_handler(impl->discretization.dof_handler);
    std::vector<
      dealii::DataComponentInterpretation::DataComponentInterpretation>
                             kinds(3,
            dealii::DataComponentInterpretation::component_is_part_of_vector);
    std::vector<std::string> names(3, "displacement");
    if (impl->discretization.layout.mixed())
      {
        kinds.push_back(
          dealii::DataComponentInterpretation::component_is_scalar);
        names.emplace_back("pressure");
      }
    data_out.add_data_vector(impl->u,
                             names,
                             dealii::DataOut<3>::type_dof_data,
                             kinds);
  }

  const dealii::Mapping<3, 3> &
  Problem::mapping() const
  {
    return impl->discretization.mapping;
  }

  dealii::types::global_dof_index
  Problem::n_dofs() const
  {
    return impl->discretization.dof_handler.n_dofs();
  }

  std::string
  Problem::linear_solver_name() const
  {
    const unsigned int depth = impl->params.chord_acceleration_depth;
    return impl->system.linear_solver->name() +
           (impl->system.linear_solver->direct() && depth > 0
              ? ", Anderson-accelerated chords (depth " +
                  std::to_string(depth) + ")"
              : "");
  }

  std::string
  Problem::discretization_name() const
  {
    return impl->discretization.layout.name();
  }

  std::array<dealii::types::global_dof_index, 2>
  Problem::n_block_dofs() const
  {
    return {{dealii::Utilities::MPI::sum(
               impl->discretization.layout.owned(0).n_elements(),
               impl->comm),
             dealii::Utilities::MPI::sum(
               impl->discretization.layout.owned(1).n_elements(),
               impl->comm)}};
  }

  std::map<std::string, double>
  Problem::timings() const
  {
    return impl->timer.get_summary_data(dealii::TimerOutput::total_wall_time);
  }
} // namespace systole::Mechanics
