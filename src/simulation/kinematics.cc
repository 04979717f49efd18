#include "simulation/kinematics.h"

#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/data_component_interpretation.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include "base/interrupt.h"
#include "base/logger.h"
#include "base/units.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "io/results_file.h"
#include "mechanics/cavity_volume.h"
#include "simulation/parameters.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace systole
{
  void
  KinematicsParameters::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Kinematics");
    prm.declare_entry(
      "Stretch amplitude",
      "0.1",
      dealii::Patterns::Double(-0.5, 1.0),
      "A in the prescribed stretch lambda(t) = 1 + A sin^2(pi t / T) about the "
      "centre of the base (Problem = cavity volume). Units: -.");
    prm.declare_entry("Period",
                      "100",
                      dealii::Patterns::Double(0.0),
                      "T in lambda(t) = 1 + A sin^2(pi t / T). Units: ms.");
    prm.declare_entry(
      "Cavities",
      "endocardium",
      dealii::Patterns::List(dealii::Patterns::Anything(), 1),
      "Boundary parts (comma-separated) that each bound a cavity closed by "
      "the plane of the base, e.g. 'lv_endocardium, rv_endocardium' on a "
      "biventricular mesh; each gets its own columns <part>_volume and <part>_volume_mL. Units: -.");
    prm.leave_subsection();
  }

  KinematicsParameters
  KinematicsParameters::parse(const dealii::ParameterHandler &prm)
  {
    KinematicsParameters p;
    p.amplitude = prm.get_double({"Kinematics"}, "Stretch amplitude");
    p.period    = prm.get_double({"Kinematics"}, "Period");
    p.cavities =
      dealii::Utilities::split_string_list(prm.get({"Kinematics"}, "Cavities"));
    AssertThrow(p.period > 0,
                dealii::ExcMessage("Kinematics / Period must be positive."));
    return p;
  }

  double
  KinematicsParameters::stretch(const double time) const
  {
    const double s = std::sin(M_PI * time / period);
    return 1.0 + amplitude * s * s;
  }

  namespace
  {
    /// u(X) = (lambda - 1) (X - centre)
    class UniformStretch : public dealii::Function<3>
    {
    public:
      UniformStretch(const double lambda, const dealii::Point<3> &centre)
        : dealii::Function<3>(3)
        , lambda(lambda)
        , centre(centre)
      {}

      double
      value(const dealii::Point<3> &p,
            const unsigned int      component) const override
      {
        return (lambda - 1.0) * (p[component] - centre[component]);
      }

    private:
      double           lambda;
      dealii::Point<3> centre;
    };

    /// The run on the log: its size and the undeformed @p volumes of the
    /// @p cavities.
    void
    log_start(const RunParameters            &run,
              const dealii::Triangulation<3> &tria,
              const dealii::DoFHandler<3>    &dof_handler,
              const std::vector<std::string> &cavities,
              const std::vector<double>      &volumes,
              Logger                         &logger,
              const MPI_Comm                  comm)
    {
      std::ostringstream o;
      o << IO::code_version() << ": problem '" << run.problem << "', "
        << tria.n_global_active_cells() << " cells, " << dof_handler.n_dofs()
        << " DOFs, " << dealii::Utilities::MPI::n_mpi_processes(comm)
        << " rank(s)";
      logger.line(o.str());
      for (unsigned int c = 0; c < volumes.size(); ++c)
        {
          o.str("");
          o << "Undeformed cavity volume"
            << (volumes.size() > 1 ? " " + cavities[c] : "") << ": "
            << std::setprecision(10) << volumes[c] << " mm^3 ("
            << Units::mm3_to_mL(volumes[c]) << " mL)";
          logger.line(o.str());
        }
    }

    /// The time-series row of a step: the stretch and the volume of each
    /// cavity (named as Problem = mechanics names its cavities).
    std::vector<IO::Column>
    volume_row(const double                    time,
               const unsigned int              step,
               const double                    lambda,
               const std::vector<std::string> &cavities,
               const std::vector<double>      &volumes)
    {
      std::vector<IO::Column> row = {{"time", "ms", time},
                                     {"step", "-", static_cast<double>(step)},
                                     {"stretch", "-", lambda}};
      for (unsigned int c = 0; c < volumes.size(); ++c)
        {
          const std::string name =
            volumes.size() > 1 ? cavities[c] + "_volume" : "volume";
          row.push_back({name, "mm^3", volumes[c]});
          row.push_back({name + "_mL", "mL", Units::mm3_to_mL(volumes[c])});
        }
      return row;
    }

    /// The displacement @p u as the fields of @p step.
    void
    write_displacement(const dealii::DoFHandler<3> &dof_handler,
                       const LA::MPI::Vector       &u,
                       const dealii::Mapping<3>    &mapping,
                       const unsigned int           subdivisions,
                       const unsigned int           step,
                       const double                 time,
                       IO::ResultsFile             &results)
    {
      dealii::DataOut<3> data_out;
      data_out.attach_dof_handler(dof_handler);
      const std::vector<
        dealii::DataComponentInterpretation::DataComponentInterpretation>
        vector(
          3,
          dealii::DataComponentInterpretation::component_is_part_of_vector);
      data_out.add_data_vector(u,
                               std::vector<std::string>(3, "displacement"),
                               dealii::DataOut<3>::type_dof_data,
                               vector);
      data_out.build_patches(mapping, subdivisions);
      results.write_fields(data_out, step, time);
    }
  } // namespace

  void
  run_cavity_volume_problem(const RunInputs &in)
  {
    const auto geometry =
      Geometry::Parameters::parse(in.prm, in.run.parameter_directory);
    const auto kinematics = KinematicsParameters::parse(in.prm);

    // Hexahedra on p4est, tetrahedra fully distributed.
    const Geometry::DistributedMesh mesh =
      Geometry::create_distributed_mesh(geometry, in.comm);
    const dealii::Triangulation<3> &tria  = *mesh.tria;
    const Geometry::BoundaryNames  &names = mesh.names;
    for (const auto &part : kinematics.cavities)
      Geometry::require_boundary(tria, names, part);
    Geometry::require_boundary(tria, names, "base");
    // The base plane (for a ruled base: the first cavity's basal ring, the
    // center of the prescribed stretch).
    const Geometry::Plane lid =
      kinematics.cavities.empty()
        ? Geometry::boundary_plane(tria, names.id("base"), "base")
        : Geometry::cavity_lid(tria, names, kinematics.cavities.front());

    const Geometry::CellKind  kind(tria);
    const dealii::FESystem<3> fe(*kind.lagrange(in.run.polynomial_degree), 3);
    dealii::DoFHandler<3>     dof_handler(tria);
    dof_handler.distribute_dofs(fe);
    const auto mapping_pointer = kind.mapping(tria, in.run.mapping_degree);
    const dealii::Mapping<3> &mapping = *mapping_pointer;
    const unsigned int        n_q =
      in.run.polynomial_degree + kind.mapping_degree(in.run.mapping_degree) + 1;

    const dealii::IndexSet owned = dof_handler.locally_owned_dofs();
    dealii::IndexSet       relevant;
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    LA::MPI::Vector u_owned(owned, in.comm);
    LA::MPI::Vector u(owned, relevant, in.comm);

    // Each cavity closed by its own lid in the common base plane: the field
    // of CavityVolume has no flux through that plane, so each lid adds 0.
    std::vector<Mechanics::CavityVolume> cavities;
    for (const auto &part : kinematics.cavities)
      cavities.emplace_back(names.id(part),
                            Geometry::cavity_lid(tria, names, part));
    const auto volumes = [&]() {
      std::vector<double> v;
      for (const auto &cavity : cavities)
        v.push_back(cavity.volume(mapping, dof_handler, u, n_q));
      return v;
    };
    const std::vector<double> volumes0 = volumes();

    log_start(in.run,
              tria,
              dof_handler,
              kinematics.cavities,
              volumes0,
              in.logger,
              in.comm);

    IO::ResultsFile results(in.run.output_directory,
                            in.parameter_text,
                            in.comm);
    Progress        progress(in.logger,
                      Progress::parse_mode(in.run.progress),
                      in.run.start_time,
                      in.run.end_time);

    const unsigned int n_steps = static_cast<unsigned int>(std::ceil(
      (in.run.end_time - in.run.start_time) / in.run.time_step - 1e-9));
    unsigned int       step    = 0;
    for (; step <= n_steps; ++step)
      {
        const double time =
          std::min(in.run.start_time + step * in.run.time_step,
                   in.run.end_time);
        const double lambda = kinematics.stretch(time);
        progress.update(step, time, "cavity volume");

        dealii::VectorTools::interpolate(mapping,
                                         dof_handler,
                                         UniformStretch(lambda, lid.point),
                                         u_owned);
        u = u_owned;

        results.append_timeseries(
          volume_row(time, step, lambda, kinematics.cavities, volumes()));
        if (in.run.field_output_interval > 0 &&
            (step % in.run.field_output_interval == 0 || step == n_steps))
          write_displacement(dof_handler,
                             u,
                             mapping,
                             kind.output_subdivisions(in.run.polynomial_degree),
                             step,
                             time,
                             results);

        if (interrupted(in.comm))
          {
            in.logger.line("Interrupted: " + results.path() +
                           " holds steps 0.." + std::to_string(step) + ".");
            break;
          }
      }
    in.logger.line("Wrote " + results.path());
  }
} // namespace systole
