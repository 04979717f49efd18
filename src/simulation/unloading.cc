#include "simulation/unloading.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
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
#include "simulation/reference_unloader.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace systole
{
  namespace
  {
    using Acceleration = UnloadingParameters::Acceleration;

    /// The log line and the time-series row of one fixed-point iteration.
    void
    report_iteration(const UnloadingIteration  &it,
                     const UnloadingParameters &up,
                     const double               image_volume,
                     Logger                    &logger,
                     IO::ResultsFile           &results)
    {
      std::ostringstream line;
      line << "Unloading iteration " << it.iteration << ": reference volume "
           << std::setprecision(6) << Units::mm3_to_mL(it.reference_volume)
           << " mL, reloaded " << Units::mm3_to_mL(it.reloaded_volume)
           << " mL (image " << Units::mm3_to_mL(image_volume)
           << " mL), reload error " << std::setprecision(3) << it.reload_error
           << " mm";
      if (up.synthetic_image)
        line << ", reference error " << it.reference_error << " mm";
      line << "; " << it.forward.steps << " load steps, " << it.forward.newton
           << " Newton iterations";
      logger.line(line.str());

      std::vector<IO::Column> row = {
        {"iteration", "-", static_cast<double>(it.iteration)},
        {"reload_max_error_mm", "mm", it.reload_error}};
      if (up.synthetic_image)
        row.push_back({"reference_max_error_mm", "mm", it.reference_error});
      row.insert(
        row.end(),
        {{"reference_volume_mL", "mL", Units::mm3_to_mL(it.reference_volume)},
         {"reloaded_volume_mL", "mL", Units::mm3_to_mL(it.reloaded_volume)},
         {"image_volume_mL", "mL", Units::mm3_to_mL(image_volume)},
         {"load_steps", "-", static_cast<double>(it.forward.steps)},
         {"step_cuts", "-", static_cast<double>(it.forward.cuts)},
         {"newton_iterations", "-", static_cast<double>(it.forward.newton)},
         {"chord_iterations", "-", static_cast<double>(it.forward.chord)},
         {"relaxation", "-", it.relaxation}});
      results.append_timeseries(row);
    }

    /// The fields of the unloaded reference @p X: the reload displacement
    /// and, beside it, the unloading displacement x_img - X at its vertices
    /// (a linear field).
    void
    write_unloading_fields(const MechanicsModel                &model,
                           const RunParameters                 &run,
                           const std::vector<dealii::Point<3>> &X,
                           const std::vector<dealii::Point<3>> &image,
                           IO::ResultsFile                     &results)
    {
      dealii::DoFHandler<3> q1(model.tria);
      // Linear (Q1 or P1) on the cells of the mesh.
      const dealii::FESystem<3> fe(*model.problem->cell_kind().lagrange(1), 3);
      q1.distribute_dofs(fe);
      dealii::Vector<double> unloading(q1.n_dofs());
      std::map<dealii::Point<3>, unsigned int, Geometry::PointLess> lookup;
      for (unsigned int i = 0; i < X.size(); ++i)
        lookup.emplace(X[i], i);
      for (const auto &cell : q1.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned int v : cell->vertex_indices())
            {
              const unsigned int i = lookup.at(cell->vertex(v));
              for (unsigned int c = 0; c < 3; ++c)
                unloading(cell->vertex_dof_index(v, c)) = image[i][c] - X[i][c];
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
      data_out.build_patches(model.problem->mapping(),
                             model.problem->cell_kind().output_subdivisions(
                               run.polynomial_degree));
      results.write_fields(data_out, 0, 0.0);
    }

    /// The summary row of the run.
    std::vector<IO::Column>
    summary_row(const UnloadingParameters            &up,
                const UnloadingResult                &unloaded,
                const SolveCounts                    &total,
                const unsigned int                    forward_solves,
                const dealii::types::global_dof_index n_dofs,
                const std::size_t                     n_vertices,
                const double                          image_volume)
    {
      std::vector<IO::Column> summary = {
        {"n_dofs", "-", static_cast<double>(n_dofs)},
        {"n_vertices", "-", static_cast<double>(n_vertices)},
        {"image_pressure_mmHg", "mmHg", Units::kPa_to_mmHg(up.image_pressure)},
        {"aitken", "-", up.acceleration == Acceleration::aitken ? 1.0 : 0.0},
        {"fixed_point_iterations",
         "-",
         static_cast<double>(unloaded.iterations)},
        {"forward_solves", "-", static_cast<double>(forward_solves)},
        {"load_steps", "-", static_cast<double>(total.steps)},
        {"step_cuts", "-", static_cast<double>(total.cuts)},
        {"newton_iterations", "-", static_cast<double>(total.newton)},
        {"chord_iterations", "-", static_cast<double>(total.chord)},
        {"linear_iterations", "-", static_cast<double>(total.linear)},
        {"reload_max_error_mm", "mm", unloaded.last.reload_error}};
      if (up.synthetic_image)
        summary.push_back(
          {"reference_max_error_mm", "mm", unloaded.last.reference_error});
      summary.insert(
        summary.end(),
        {{"unloaded_volume_mL",
          "mL",
          Units::mm3_to_mL(unloaded.last.reference_volume)},
         {"reloaded_volume_mL",
          "mL",
          Units::mm3_to_mL(unloaded.last.reloaded_volume)},
         {"image_volume_mL", "mL", Units::mm3_to_mL(image_volume)}});
      return summary;
    }
  } // namespace

  void
  run_unloading_problem(const RunInputs &in)
  {
    const auto up = UnloadingParameters::parse(in.prm);
    const auto fibre_params =
      Fibres::Parameters::parse(in.prm, in.run.parameter_directory);

    MechanicsModel    model(in.prm, in.run, in.logger, in.comm);
    ReferenceUnloader unloader(model, in.run, fibre_params, in.logger, in.comm);
    auto             &tria = model.tria;
    in.logger.line(model.banner(in.run));
    {
      std::ostringstream o;
      o << "Unloading from " << Units::kPa_to_mmHg(up.image_pressure)
        << " mmHg ("
        << (up.acceleration == UnloadingParameters::Acceleration::aitken
              ? "Aitken relaxation"
              : "plain fixed point")
        << ", tolerance " << up.tolerance << " mm)"
        << (up.synthetic_image ? ", synthetic image" : "");
      in.logger.line(o.str());
    }

    const std::vector<dealii::Point<3>> given = unloader.vertices();
    std::vector<dealii::Point<3>>       image = given;
    IO::ResultsFile                     results(in.run.output_directory,
                            in.parameter_text,
                            in.comm);

    SolveCounts  total;
    unsigned int forward_solves   = 0;
    double       synthetic_volume = 0;
    if (up.synthetic_image)
      {
        in.logger.line("Synthetic image: inflating the given geometry");
        total += unloader.inflate(up.image_pressure);
        ++forward_solves;
        synthetic_volume = model.problem->cavity_volume();
        const auto u     = unloader.displacements();
        for (unsigned int i = 0; i < image.size(); ++i)
          image[i] = given[i] + u[i];
        unloader.set_vertices(image);
      }
    const double image_volume =
      up.synthetic_image ? synthetic_volume : model.problem->cavity_volume();

    const auto on_iteration = [&](const UnloadingIteration &it) {
      report_iteration(it, up, image_volume, in.logger, results);
    };
    const auto unloaded = unloader.unload(image,
                                          up,
                                          up.synthetic_image ? &given : nullptr,
                                          on_iteration);
    total += unloaded.totals;
    forward_solves += unloaded.forward_solves;
    const unsigned int k = unloaded.iterations;
    const auto        &X = unloader.vertices();

    // The unloaded reference: the mesh, the unloading displacement x_img - X
    // at its vertices (a linear field) beside the reload displacement.
    const std::string mesh_path = in.run.output_directory + "/" + up.mesh_file;
    Geometry::write_gmsh(tria, model.names, mesh_path);
    if (in.run.field_output_interval > 0)
      write_unloading_fields(model, in.run, X, image, results);
    results.append_summary(summary_row(up,
                                       unloaded,
                                       total,
                                       forward_solves,
                                       model.problem->n_dofs(),
                                       X.size(),
                                       image_volume));
    std::vector<std::pair<std::string, std::string>> texts;
    auto statistics = model.statistics(texts);
    unloader.add_earlier_timings(statistics);
    statistics.insert(
      statistics.end(),
      {{"forward_solves", "-", static_cast<double>(forward_solves)},
       {"fixed_point_iterations", "-", static_cast<double>(k)},
       {"newton_iterations", "-", static_cast<double>(total.newton)}});
    results.write_statistics(statistics, texts);
    in.logger.line("Unloaded in " + std::to_string(k) + " iterations (" +
                   std::to_string(forward_solves) + " forward solves); wrote " +
                   mesh_path + " and " + results.path());
  }
} // namespace systole
