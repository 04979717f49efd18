#include "simulation/unloading.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include "base/errors.h"
#include "base/logger.h"
#include "base/units.h"
#include "fibres/fibre_field.h"
#include "geometry/gmsh_export.h"
#include "geometry/point_less.h"
#include "io/results_file.h"
#include "mechanics/problem.h"
#include "simulation/mechanics_model.h"
#include "simulation/parameters.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace systole
{
  void
  UnloadingParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Unloading");
    prm.declare_entry(
      "Image pressure",
      "10",
      Double(0.0),
      "Problem = unloading: the cavity pressure at which the geometry of "
      "subsection Geometry was imaged (end-diastole). The stress-free "
      "reference is the one that this pressure inflates to that geometry. "
      "Units: mmHg (converted to kPa inside).");
    prm.declare_entry(
      "Tolerance",
      "0.01",
      Double(0.0),
      "Problem = unloading: stop when the reference, inflated to the image "
      "pressure, matches the imaged vertices to this distance (maximum over "
      "the vertices of |X + u(X) - x_img|). Units: mm.");
    prm.declare_entry(
      "Maximum iterations",
      "30",
      Integer(1),
      "Problem = unloading: fixed-point updates of the "
      "reference before the run stops with an error. Units: -.");
    prm.declare_entry(
      "Acceleration",
      "aitken",
      Selection("aitken|none"),
      "Problem = unloading: relaxation of the backward-displacement update "
      "X <- X + omega (x_img - X - u(X)). none: omega = 1 (Sellier's plain "
      "fixed point). aitken: Aitken's dynamic relaxation (Irons and Tuck; "
      "Kuettler and Wall 2008), omega from the last two residuals of the "
      "whole vertex field.");
    prm.declare_entry(
      "Synthetic image",
      "false",
      Bool(),
      "Problem = unloading: a round trip with a known truth. First inflate "
      "the geometry of subsection Geometry to the image pressure and take "
      "the inflated vertices as the image (the geometry itself is then only "
      "used to measure the recovered reference: reference_max_error_mm). "
      "Units: -.");
    prm.declare_entry(
      "Mesh file",
      "unloaded.msh",
      Anything(),
      "Problem = unloading: name of the gmsh file (format 2.2, ASCII, in the "
      "run folder <Directory>/<Run name>) that receives the unloaded mesh, "
      "with the boundary parts' names as physical surfaces, for Geometry / "
      "Type = gmsh. Units: -.");
    prm.leave_subsection();
  }

  UnloadingParameters
  UnloadingParameters::parse(const dealii::ParameterHandler &prm)
  {
    UnloadingParameters p;
    const std::string   s = "Unloading";
    p.image_pressure =
      Units::mmHg_to_kPa(prm.get_double({s}, "Image pressure"));
    p.tolerance       = prm.get_double({s}, "Tolerance");
    p.max_iterations  = prm.get_integer({s}, "Maximum iterations");
    p.acceleration    = prm.get({s}, "Acceleration") == "none"
                          ? Acceleration::none
                          : Acceleration::aitken;
    p.synthetic_image = prm.get_bool({s}, "Synthetic image");
    p.mesh_file       = prm.get({s}, "Mesh file");
    AssertThrow(p.image_pressure > 0.0,
                dealii::ExcMessage(
                  "Unloading / Image pressure must be positive (mmHg): at "
                  "zero pressure the imaged geometry is its own reference."));
    AssertThrow(p.tolerance > 0.0,
                dealii::ExcMessage(
                  "Unloading / Tolerance must be positive (mm), e.g. 0.01."));
    AssertThrow(!p.mesh_file.empty() &&
                  p.mesh_file.find('/') == std::string::npos,
                dealii::ExcMessage("Unloading / Mesh file must be a plain "
                                   "file name (it is written in the run "
                                   "folder), e.g. unloaded.msh."));
    return p;
  }

  namespace
  {
    /// What the load steps of one forward solve did.
    struct ForwardReport
    {
      unsigned int load_steps = 0, cuts = 0, newton = 0, chord = 0, linear = 0;
    };

    /// Ramp the pressure from 0 to @p pressure [kPa] on @p problem (which
    /// starts at zero displacement), as Problem = mechanics does: the first
    /// increment 1 / Load steps, the predictor of the last two states,
    /// increments adapted to the Newton iterations, a failed step halved up
    /// to Maximum step cuts times.
    ForwardReport
    inflate(Mechanics::Problem          &problem,
            const Mechanics::Parameters &params,
            const double                 pressure,
            Logger                      &logger)
    {
      ForwardReport report;
      const double  nominal        = 1.0 / params.load_steps;
      double        fraction       = 0.0;
      double        increment      = nominal;
      double        last_increment = nominal;
      problem.save();
      while (fraction < 1.0 - 1e-12)
        {
          increment           = std::min(increment, 1.0 - fraction);
          const double target = fraction + increment;
          problem.predict(std::min(increment / last_increment, 1.0),
                          target * pressure,
                          0.0);
          try
            {
              const auto r = problem.solve(target * pressure, 0.0);
              problem.save();
              report.newton += r.iterations;
              report.chord += r.reused_iterations;
              report.linear += r.linear_iterations;
              ++report.load_steps;
              fraction       = target;
              last_increment = increment;
              if (params.adaptive_load_steps && r.iterations <= 4)
                increment *= 1.5;
              else if (params.adaptive_load_steps && r.iterations >= 8)
                increment *= 0.5;
            }
          catch (const ExcNewtonDidNotConverge &e)
            {
              problem.restore();
              ++report.cuts;
              AssertThrow(report.cuts <= params.max_step_cuts,
                          dealii::ExcMessage(
                            "Unloading: a forward solve did not converge at "
                            "load fraction " +
                            dealii::Utilities::to_string(target) + " after " +
                            std::to_string(params.max_step_cuts) +
                            " step cuts (" + one_line_message(e) +
                            "). The reference may have become too distorted: "
                            "try Unloading / Acceleration = none or more "
                            "Mechanics / Load steps."));
              increment *= 0.5;
              logger.stream()
                << "  Newton failed (" << one_line_message(e)
                << "); cutting the load step to " << increment << std::endl;
            }
        }
      return report;
    }

    /// The vertices of the whole mesh, the same table on every rank, sorted by
    /// their first reference position (so that sums over it do not depend on
    /// the partition), and where each vertex of this rank's mesh sits in it.
    class VertexTable
    {
    public:
      /// From the vertices of @p problem (its mesh's current positions).
      VertexTable(const Mechanics::Problem                        &problem,
                  dealii::parallel::distributed::Triangulation<3> &tria)
      {
        const auto gathered = gather(problem, tria.get_communicator());
        for (std::size_t i = 0; i < gathered.size(); i += 6)
          X.emplace_back(gathered[i], gathered[i + 1], gathered[i + 2]);
        std::sort(X.begin(), X.end(), Geometry::PointLess());
        const auto lookup = index();
        record.assign(tria.n_vertices(), dealii::numbers::invalid_unsigned_int);
        for (const auto &cell : tria.active_cell_iterators())
          if (!cell->is_artificial())
            for (const unsigned int v : cell->vertex_indices())
              {
                const auto it = lookup.find(cell->vertex(v));
                AssertThrow(it != lookup.end(),
                            dealii::ExcMessage(
                              "Unloading: a vertex of this rank's cells is "
                              "not in the gathered vertex table (the ranks "
                              "disagree on its coordinates)."));
                record[cell->vertex_index(v)] = it->second;
              }
      }

      /// The displacement u of @p problem at every vertex of the table
      /// (collective): X holds its mesh's positions.
      std::vector<dealii::Tensor<1, 3>>
      displacements(const Mechanics::Problem &problem,
                    const MPI_Comm            comm) const
      {
        const auto                        gathered = gather(problem, comm);
        const auto                        lookup   = index();
        std::vector<dealii::Tensor<1, 3>> u(X.size());
        std::size_t                       found = 0;
        for (std::size_t i = 0; i < gathered.size(); i += 6)
          {
            const dealii::Point<3> reference(gathered[i],
                                             gathered[i + 1],
                                             gathered[i + 2]);
            const auto             it = lookup.find(reference);
            AssertThrow(it != lookup.end(),
                        dealii::ExcMessage("Unloading: a vertex of the "
                                           "mechanics is not in the table."));
            for (unsigned int d = 0; d < 3; ++d)
              u[it->second][d] = gathered[i + 3 + d] - reference[d];
            ++found;
          }
        AssertThrow(found == X.size(),
                    dealii::ExcMessage("Unloading: the mechanics returned " +
                                       std::to_string(found) + " of " +
                                       std::to_string(X.size()) +
                                       " vertices."));
        return u;
      }

      /// Move every vertex of @p tria that the table knows to its position
      /// in X (all levels: the vertices are shared).
      void
      move(dealii::parallel::distributed::Triangulation<3> &tria) const
      {
        for (const auto &cell : tria.cell_iterators())
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int r = record[cell->vertex_index(v)];
              if (r != dealii::numbers::invalid_unsigned_int)
                cell->vertex(v) = X[r];
            }
      }

      /// Current positions, one per vertex of the mesh [mm].
      std::vector<dealii::Point<3>> X;

    private:
      /// [X, x] of the vertices whose DoFs this rank owns, all ranks in order.
      static std::vector<double>
      gather(const Mechanics::Problem &problem, const MPI_Comm comm)
      {
        std::vector<double> mine;
        for (const auto &s : problem.vertex_states())
          for (const auto &p : {s.reference, s.deformed})
            for (unsigned int d = 0; d < 3; ++d)
              mine.push_back(p[d]);
        std::vector<double> all;
        for (const auto &part : dealii::Utilities::MPI::all_gather(comm, mine))
          all.insert(all.end(), part.begin(), part.end());
        return all;
      }

      std::map<dealii::Point<3>, unsigned int, Geometry::PointLess>
      index() const
      {
        std::map<dealii::Point<3>, unsigned int, Geometry::PointLess> lookup;
        for (unsigned int i = 0; i < X.size(); ++i)
          lookup.emplace(X[i], i);
        AssertThrow(lookup.size() == X.size(),
                    dealii::ExcMessage(
                      "Unloading: two vertices of the reference coincide "
                      "(the reference is degenerate)."));
        return lookup;
      }

      /// Per vertex index of this rank's mesh: its row in X (or invalid).
      std::vector<unsigned int> record;
    };

    double
    max_distance(const std::vector<dealii::Tensor<1, 3>> &d)
    {
      double m = 0;
      for (const auto &v : d)
        m = std::max(m, v.norm());
      return m;
    }
  } // namespace

  void
  run_unloading_problem(const dealii::ParameterHandler &prm,
                        const RunParameters            &run,
                        const std::string              &parameter_text,
                        Logger                         &logger,
                        const MPI_Comm                  comm)
  {
    const auto up = UnloadingParameters::parse(prm);
    const auto fibre_params =
      Fibres::Parameters::parse(prm, run.parameter_directory);
    AssertThrow(
      fibre_params.generator == "rule-based" ||
        fibre_params.generator == "cartesian",
      dealii::ExcMessage(
        "Problem = unloading computes the fibres on every trial reference: "
        "Fibres / Generator must be rule-based (or cartesian), not " +
        fibre_params.generator +
        " (the analytic rule needs the generated ellipsoid, a DTI image "
        "lives in the loaded geometry)."));

    MechanicsModel model(prm, run, logger, comm);
    AssertThrow(model.problem->n_cavities() == 1,
                dealii::ExcMessage(
                  "Problem = unloading needs one cavity: Mechanics / Pressure "
                  "boundary names one boundary part (the endocardium) and the "
                  "mesh has a part 'base'."));
    auto &tria = model.tria;
    // The reference is its vertices: a moved vertex must not snap back to a
    // curved manifold of the generator, and the mapping (MappingQ of the
    // flat manifold: trilinear cells) follows the moved vertices. The
    // written gmsh mesh stores the same trilinear cells.
    tria.set_all_manifold_ids(dealii::numbers::flat_manifold_id);
    tria.reset_all_manifolds();

    // The mechanics' timer sections summed over the problems of all the
    // trial references (each rebuild starts its own timers).
    std::map<std::string, double> earlier_timings;
    const auto                    rebuild = [&]() {
      for (const auto &[section, seconds] : model.problem->timings())
        earlier_timings[section] += seconds;
      model.problem.reset();
      model.problem = std::make_unique<Mechanics::Problem>(
        model.params,
        tria,
        model.names,
        run.polynomial_degree,
        run.mapping_degree,
        *model.passive,
        model.volumetric,
        Fibres::create_fibre_field(fibre_params,
                                   model.geometry.lv_shape,
                                   tria,
                                   model.names,
                                   &logger),
        logger);
    };
    rebuild();
    logger.line(model.banner(run));
    {
      std::ostringstream o;
      o << "Unloading from " << Units::kPa_to_mmHg(up.image_pressure)
        << " mmHg ("
        << (up.acceleration == UnloadingParameters::Acceleration::aitken
              ? "Aitken relaxation"
              : "plain fixed point")
        << ", tolerance " << up.tolerance << " mm)"
        << (up.synthetic_image ? ", synthetic image" : "");
      logger.line(o.str());
    }

    VertexTable                         table(*model.problem, tria);
    const std::vector<dealii::Point<3>> given = table.X;
    std::vector<dealii::Point<3>>       image = given;
    IO::ResultsFile results(run.output_directory, parameter_text, comm);

    ForwardReport total;
    unsigned int  forward_solves = 0;
    const auto    forward        = [&]() {
      const auto r =
        inflate(*model.problem, model.params, up.image_pressure, logger);
      total.load_steps += r.load_steps;
      total.cuts += r.cuts;
      total.newton += r.newton;
      total.chord += r.chord;
      total.linear += r.linear;
      ++forward_solves;
      return r;
    };

    double synthetic_volume = 0;
    if (up.synthetic_image)
      {
        logger.line("Synthetic image: inflating the given geometry");
        forward();
        synthetic_volume = model.problem->cavity_volume();
        const auto u     = table.displacements(*model.problem, comm);
        for (unsigned int i = 0; i < image.size(); ++i)
          image[i] = given[i] + u[i];
        table.X = image;
        table.move(tria);
        rebuild();
      }
    const double image_volume =
      up.synthetic_image ? synthetic_volume : model.problem->cavity_volume();

    // X_{k+1} = X_k + omega_k R_k, R_k = x_img - X_k - u(X_k): the residual
    // of Sellier's map G(X) = x_img - u(X). Aitken: omega_k = -omega_{k-1}
    // R_{k-1}.(R_k - R_{k-1}) / |R_k - R_{k-1}|^2, the secant step of the
    // whole field along its last direction; sums over the vertex table, in
    // the same order on every rank and for every partition.
    std::vector<dealii::Tensor<1, 3>> residual, last_residual;
    double                            omega = 1.0;
    unsigned int                      k     = 0;
    double reload_error = 0, reference_error = 0, reference_volume = 0,
           reloaded_volume = 0;
    for (;; ++k)
      {
        reference_volume = model.problem->cavity_volume();
        const auto r     = forward();
        reloaded_volume  = model.problem->cavity_volume();
        const auto u     = table.displacements(*model.problem, comm);
        residual.assign(u.size(), dealii::Tensor<1, 3>());
        std::vector<dealii::Tensor<1, 3>> to_truth(u.size());
        for (unsigned int i = 0; i < u.size(); ++i)
          {
            residual[i] = image[i] - table.X[i] - u[i];
            to_truth[i] = table.X[i] - given[i];
          }
        reload_error    = max_distance(residual);
        reference_error = max_distance(to_truth);

        if (k > 0 &&
            up.acceleration == UnloadingParameters::Acceleration::aitken)
          {
            double num = 0, den = 0;
            for (unsigned int i = 0; i < residual.size(); ++i)
              {
                const auto dR = residual[i] - last_residual[i];
                num += last_residual[i] * dR;
                den += dR * dR;
              }
            if (den > 0)
              omega = -omega * num / den;
          }

        std::ostringstream line;
        line << "Unloading iteration " << k << ": reference volume "
             << std::setprecision(6) << Units::mm3_to_mL(reference_volume)
             << " mL, reloaded " << Units::mm3_to_mL(reloaded_volume)
             << " mL (image " << Units::mm3_to_mL(image_volume)
             << " mL), reload error " << std::setprecision(3) << reload_error
             << " mm";
        if (up.synthetic_image)
          line << ", reference error " << reference_error << " mm";
        line << "; " << r.load_steps << " load steps, " << r.newton
             << " Newton iterations";
        logger.line(line.str());

        std::vector<IO::Column> row = {
          {"iteration", "-", static_cast<double>(k)},
          {"reload_max_error_mm", "mm", reload_error}};
        if (up.synthetic_image)
          row.push_back({"reference_max_error_mm", "mm", reference_error});
        row.insert(
          row.end(),
          {{"reference_volume_mL", "mL", Units::mm3_to_mL(reference_volume)},
           {"reloaded_volume_mL", "mL", Units::mm3_to_mL(reloaded_volume)},
           {"image_volume_mL", "mL", Units::mm3_to_mL(image_volume)},
           {"load_steps", "-", static_cast<double>(r.load_steps)},
           {"step_cuts", "-", static_cast<double>(r.cuts)},
           {"newton_iterations", "-", static_cast<double>(r.newton)},
           {"chord_iterations", "-", static_cast<double>(r.chord)},
           {"relaxation", "-", reload_error <= up.tolerance ? 0.0 : omega}});
        results.append_timeseries(row);

        if (reload_error <= up.tolerance)
          break;
        AssertThrow(k < up.max_iterations,
                    dealii::ExcMessage(
                      "Unloading did not converge in Unloading / Maximum "
                      "iterations = " +
                      std::to_string(up.max_iterations) +
                      " iterations (reload error " +
                      dealii::Utilities::to_string(reload_error) +
                      " mm > Unloading / Tolerance = " +
                      dealii::Utilities::to_string(up.tolerance) +
                      " mm); the results file holds every iteration."));
        for (unsigned int i = 0; i < residual.size(); ++i)
          table.X[i] += omega * residual[i];
        last_residual = residual;
        table.move(tria);
        rebuild();
      }

    // The unloaded reference: the mesh, the unloading displacement x_img - X
    // at its vertices (a Q1 field) beside the reload displacement.
    const std::string mesh_path = run.output_directory + "/" + up.mesh_file;
    Geometry::write_gmsh(tria, model.names, mesh_path);
    if (run.field_output_interval > 0)
      {
        dealii::DoFHandler<3>     q1(tria);
        const dealii::FESystem<3> fe(dealii::FE_Q<3>(1), 3);
        q1.distribute_dofs(fe);
        dealii::Vector<double> unloading(q1.n_dofs());
        std::map<dealii::Point<3>, unsigned int, Geometry::PointLess> lookup;
        for (unsigned int i = 0; i < table.X.size(); ++i)
          lookup.emplace(table.X[i], i);
        for (const auto &cell : q1.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int v : cell->vertex_indices())
              {
                const unsigned int i = lookup.at(cell->vertex(v));
                for (unsigned int c = 0; c < 3; ++c)
                  unloading(cell->vertex_dof_index(v, c)) =
                    image[i][c] - table.X[i][c];
              }
        dealii::DataOut<3> data_out;
        model.problem->attach_output(data_out);
        data_out.add_data_vector(
          q1,
          unloading,
          std::vector<std::string>(3, "unloading_displacement"),
          std::vector<
            dealii::DataComponentInterpretation::DataComponentInterpretation>(
            3,
            dealii::DataComponentInterpretation::component_is_part_of_vector));
        data_out.build_patches(model.problem->mapping(), run.polynomial_degree);
        results.write_fields(data_out, 0, 0.0);
      }

    std::vector<IO::Column> summary = {
      {"n_dofs", "-", static_cast<double>(model.problem->n_dofs())},
      {"n_vertices", "-", static_cast<double>(table.X.size())},
      {"image_pressure_mmHg", "mmHg", Units::kPa_to_mmHg(up.image_pressure)},
      {"aitken",
       "-",
       up.acceleration == UnloadingParameters::Acceleration::aitken ? 1.0
                                                                    : 0.0},
      {"fixed_point_iterations", "-", static_cast<double>(k)},
      {"forward_solves", "-", static_cast<double>(forward_solves)},
      {"load_steps", "-", static_cast<double>(total.load_steps)},
      {"step_cuts", "-", static_cast<double>(total.cuts)},
      {"newton_iterations", "-", static_cast<double>(total.newton)},
      {"chord_iterations", "-", static_cast<double>(total.chord)},
      {"linear_iterations", "-", static_cast<double>(total.linear)},
      {"reload_max_error_mm", "mm", reload_error}};
    if (up.synthetic_image)
      summary.push_back({"reference_max_error_mm", "mm", reference_error});
    summary.insert(
      summary.end(),
      {{"unloaded_volume_mL", "mL", Units::mm3_to_mL(reference_volume)},
       {"reloaded_volume_mL", "mL", Units::mm3_to_mL(reloaded_volume)},
       {"image_volume_mL", "mL", Units::mm3_to_mL(image_volume)}});
    results.append_summary(summary);
    std::vector<std::pair<std::string, std::string>> texts;
    auto statistics = model.statistics(texts);
    for (auto &column : statistics)
      for (const auto &[section, seconds] : earlier_timings)
        if (column.name ==
            "timer: " +
              dealii::Utilities::replace_in_string(section, " / ", ": "))
          column.value += seconds;
    statistics.insert(
      statistics.end(),
      {{"forward_solves", "-", static_cast<double>(forward_solves)},
       {"fixed_point_iterations", "-", static_cast<double>(k)},
       {"newton_iterations", "-", static_cast<double>(total.newton)}});
    results.write_statistics(statistics, texts);
    logger.line("Unloaded in " + std::to_string(k) + " iterations (" +
                std::to_string(forward_solves) + " forward solves); wrote " +
                mesh_path + " and " + results.path());
  }
} // namespace systole
