#include "postprocess/manager.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/numerics/data_out.h>

#include "postprocess/factory.h"
#include "postprocess/lv_wall.h"

#include <algorithm>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>

namespace systole::Postprocess
{
  void
  Parameters::declare(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Postprocess");
    prm.declare_entry(
      "List of postprocessors",
      "",
      dealii::Patterns::List(dealii::Patterns::Anything()),
      "Comma-separated names of the postprocessors that run after every "
      "accepted step of a heartbeat or mechanics problem (none by default). " +
        postprocessor_descriptions() +
        " Fields are written with the others every Output / Field output "
        "interval steps; strain, AHA segments, clinical kinematics and "
        "ventricle function need a left ventricle (boundary parts "
        "endocardium, epicardium, base) or two ventricles (lv_endocardium, "
        "rv_endocardium, epicardium, base), where they measure the LV wall "
        "(the LV free wall and the septum) and the first cavity (the LV).");
    prm.enter_subsection("AHA segments");
    prm.declare_entry(
      "Reference direction",
      "0, 1, 0",
      dealii::Patterns::List(dealii::Patterns::Double(), 3, 3),
      "The anterior direction: the circumferential angle of the AHA "
      "segments is measured from it (projected onto the plane normal to the "
      "long axis), counter-clockwise seen from the apex, so that 0 degrees "
      "is the centre of segments 1 (basal anterior), 7 and 13, and 90 "
      "degrees the septum (segments 2-3, 8-9, 14; on two ventricles the "
      "run stops if the RV lies outside 45 to 135 degrees). Units: - (a "
      "direction; its length does not matter).");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  Parameters
  Parameters::parse(const dealii::ParameterHandler &prm)
  {
    Parameters p;
    for (const auto &name : dealii::Utilities::split_string_list(
           prm.get({"Postprocess"}, "List of postprocessors")))
      {
        create_postprocessor(name); // throws naming the valid ones
        AssertThrow(std::find(p.postprocessors.begin(),
                              p.postprocessors.end(),
                              name) == p.postprocessors.end(),
                    dealii::ExcMessage("Postprocess / List of postprocessors "
                                       "names '" +
                                       name + "' twice."));
        p.postprocessors.push_back(name);
      }
    const auto d =
      dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(
        prm.get({"Postprocess", "AHA segments"}, "Reference direction")));
    for (unsigned int i = 0; i < 3; ++i)
      p.reference_direction[i] = d[i];
    AssertThrow(p.reference_direction.norm() > 0,
                dealii::ExcMessage("Postprocess / AHA segments / Reference "
                                   "direction must not be zero."));
    return p;
  }

  struct Manager::Impl
  {
    Impl(const Parameters              &params,
         const Mechanics::Problem      &problem,
         const Geometry::BoundaryNames &names,
         Logger                        *logger)
      : problem(problem)
      , tria(problem.triangulation())
      , comm(tria.get_communicator())
    {
      for (const auto &name : params.postprocessors)
        postprocessors.push_back(create_postprocessor(name));
      for (const auto &p : postprocessors)
        {
          const Needs n = p->needs();
          needs.cardiac_frame |= n.cardiac_frame;
          needs.segments |= n.segments;
          needs.vertices |= n.vertices;
          needs.areas |= n.areas;
          for (const auto &f : p->field_names())
            {
              fields.emplace_back(p.get(), field_names.size());
              field_names.push_back(f);
            }
        }
      // fields[i] = (postprocessor, global index): turn the index into the
      // postprocessor's own.
      {
        unsigned int i = 0;
        for (const auto &p : postprocessors)
          for (unsigned int k = 0; k < p->field_names().size(); ++k)
            fields[i++].second = k;
      }
      if (postprocessors.empty())
        return;
      const bool ventricle =
        needs.cardiac_frame || needs.segments || needs.areas || needs.vertices;
      if (ventricle)
        lv_wall.emplace(tria, names, needs.cardiac_frame, logger);
      std::vector<std::vector<dealii::Point<3>>> points;
      problem.quadrature_points(points);
      if (needs.cardiac_frame)
        {
          frames.assign(points.size(), {});
          std::vector<Fibres::WallFrame> wf;
          for (const auto &cell : tria.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                const auto c = cell->active_cell_index();
                lv_wall->frames(cell, points[c], wf);
                for (const auto &w : wf)
                  frames[c].push_back({w.e_c, w.e_l, w.e_t, w.transmural});
              }
        }
      if (needs.segments)
        {
          aha.emplace(AhaSegments::axis_of(tria,
                                           names,
                                           *lv_wall,
                                           params.reference_direction));
          if (lv_wall->biventricular())
            check_septum();
          // The segment of a point: that of its reference position.
          std::vector<std::vector<Mechanics::PointState>> s;
          problem.point_states(s);
          point_segments.assign(points.size(), {});
          for (const auto &cell : tria.active_cell_iterators())
            if (cell->is_locally_owned())
              {
                const auto           c       = cell->active_cell_index();
                const bool           counted = lv_wall->contains(cell);
                std::array<bool, 17> in_cell{};
                for (const auto &p : s[c])
                  {
                    const unsigned int segment = aha->segment(p.position);
                    point_segments[c].push_back(segment);
                    if (counted)
                      {
                        segment_volume[segment - 1] += p.JxW;
                        in_cell[segment - 1] = true;
                      }
                  }
                for (unsigned int k = 0; k < 17; ++k)
                  segment_count[k] += in_cell[k] ? 1 : 0;
              }
        }
      if (needs.vertices && lv_wall->biventricular())
        for (const auto &cell : tria.active_cell_iterators())
          if (!cell->is_artificial() && lv_wall->contains(cell))
            for (const unsigned int v : cell->vertex_indices())
              wall_vertices.insert(std::array<double, 3>{
                {cell->vertex(v)[0], cell->vertex(v)[1], cell->vertex(v)[2]}});
    }

    /// Two ventricles: the septum (the side of the RV's centroid) must lie
    /// in the septal segments, about 90 degrees from the reference
    /// direction.
    void
    check_septum() const
    {
      const double degrees = aha->angle(lv_wall->rv_centroid()) * 180 / M_PI;
      if (degrees >= 45 && degrees <= 135)
        return;
      // The reference that puts the septum at 90 degrees: s x (-e), s the
      // septum's direction in the short-axis plane.
      const auto          &axis = aha->axis();
      dealii::Tensor<1, 3> s    = lv_wall->rv_centroid() - axis.apex;
      s -= (s * axis.direction) * axis.direction;
      const dealii::Tensor<1, 3> reference =
        dealii::cross_product_3d(s / s.norm(), -axis.direction);
      std::ostringstream o;
      o << std::fixed << std::setprecision(3)
        << "Postprocess / AHA segments / Reference "
        << "direction: the septum of the two ventricles (toward the RV) lies "
        << "at " << degrees << " degrees from it, outside the septal "
        << "segments (45 to 135 degrees); set it to " << reference[0] << ", "
        << reference[1] << ", " << reference[2]
        << " to put the septum at 90 degrees.";
      AssertThrow(false, dealii::ExcMessage(o.str()));
    }

    void
    evaluate(const double       time,
             const unsigned int beat,
             const double       beat_start,
             const double       cavity_volume)
    {
      problem.point_states(states);
      quantities.assign(states.size(), {});
      for (unsigned int c = 0; c < states.size(); ++c)
        for (unsigned int q = 0; q < states[c].size(); ++q)
          {
            const auto &s = states[c][q];
            quantities[c].push_back(
              point_quantities(s.F,
                               s.basis,
                               s.cauchy_stress,
                               s.active_tension,
                               frames.empty() ? nullptr : &frames[c][q]));
          }
      if (needs.vertices)
        {
          vertices = problem.vertex_states();
          if (lv_wall->biventricular())
            vertices.erase(std::remove_if(vertices.begin(),
                                          vertices.end(),
                                          [&](const auto &v) {
                                            return wall_vertices.count(
                                                     {{v.reference[0],
                                                       v.reference[1],
                                                       v.reference[2]}}) == 0;
                                          }),
                           vertices.end());
        }
      data               = StepData();
      data.time          = time;
      data.beat          = beat;
      data.beat_start    = beat_start;
      data.cavity_volume = cavity_volume;
      data.points        = &states;
      data.quantities    = &quantities;
      data.comm          = comm;
      if (needs.cardiac_frame)
        data.frames = &frames;
      if (needs.segments)
        {
          data.segments       = &*aha;
          data.point_segments = &point_segments;
        }
      if (needs.vertices)
        data.vertices = &vertices;
      if (lv_wall && lv_wall->biventricular())
        data.wall_cells = &lv_wall->cells();
      if (needs.areas)
        {
          data.endocardial_area = problem.deformed_area(lv_wall->endocardium());
          const std::vector<bool> *cells =
            lv_wall->biventricular() ? &lv_wall->cells() : nullptr;
          data.epicardial_area = 0;
          for (const std::string &part : lv_wall->outer_surface())
            data.epicardial_area += problem.deformed_area(part, cells);
        }
    }

    /// The lumped L2 projection of every field onto Q1 nodes.
    void
    project()
    {
      if (!dof_handler)
        {
          dof_handler.emplace(tria);
          dof_handler->distribute_dofs(fe);
          const dealii::IndexSet owned = dof_handler->locally_owned_dofs();
          dealii::IndexSet       relevant;
          dealii::DoFTools::extract_locally_relevant_dofs(*dof_handler,
                                                          relevant);
          constraints.reinit(relevant);
          dealii::DoFTools::make_hanging_node_constraints(*dof_handler,
                                                          constraints);
          constraints.close();
          nodal.resize(field_names.size());
          for (auto &v : nodal)
            v.reinit(owned, relevant, comm);
          weights.reinit(owned, relevant, comm);
        }
      const dealii::Quadrature<3> quadrature =
        problem.cell_kind().cell_quadrature(problem.n_quadrature_points_1d());
      dealii::FEValues<3> fe_values(problem.mapping(),
                                    fe,
                                    quadrature,
                                    dealii::update_values |
                                      dealii::update_JxW_values);
      for (auto &v : nodal)
        v = 0;
      weights = 0;
      std::vector<dealii::types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler->active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            cell->get_dof_indices(dofs);
            const auto &q_values = quantities[cell->active_cell_index()];
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              for (unsigned int i = 0; i < dofs.size(); ++i)
                {
                  const double w =
                    fe_values.shape_value(i, q) * fe_values.JxW(q);
                  weights(dofs[i]) += w;
                  for (unsigned int f = 0; f < fields.size(); ++f)
                    nodal[f](dofs[i]) +=
                      w * fields[f].first->field_value(fields[f].second,
                                                       q_values[q]);
                }
          }
      weights.compress(dealii::VectorOperation::add);
      for (auto &v : nodal)
        {
          v.compress(dealii::VectorOperation::add);
          for (const auto i : v.locally_owned_elements())
            v(i) = weights(i) != 0 ? v(i) / weights(i) : 0.0;
          constraints.distribute(v);
          v.update_ghost_values();
        }
    }

    const Mechanics::Problem                             &problem;
    const dealii::Triangulation<3, 3>                    &tria;
    MPI_Comm                                              comm;
    std::vector<std::unique_ptr<Postprocessor>>           postprocessors;
    Needs                                                 needs;
    std::vector<std::pair<Postprocessor *, unsigned int>> fields;
    std::vector<std::string>                              field_names;
    std::optional<LvWall>                                 lv_wall;
    /// Two ventricles: the reference positions of the LV wall's vertices.
    std::set<std::array<double, 3>>                 wall_vertices;
    std::vector<std::vector<CardiacFrame>>          frames;
    std::optional<AhaSegments>                      aha;
    std::vector<std::vector<unsigned int>>          point_segments;
    std::array<double, 17>                          segment_volume{};
    std::array<unsigned int, 17>                    segment_count{};
    std::vector<std::vector<Mechanics::PointState>> states;
    std::vector<std::vector<PointQuantities>>       quantities;
    std::vector<Mechanics::VertexState>             vertices;
    StepData                                        data;
    bool                                            evaluated = false;

    /// Nodal fields: continuous linear elements of the mesh's cell shape.
    const std::unique_ptr<dealii::FiniteElement<3, 3>> fe_storage =
      problem.cell_kind().lagrange(1);
    const dealii::FiniteElement<3, 3>   &fe = *fe_storage;
    std::optional<dealii::DoFHandler<3>> dof_handler;
    dealii::AffineConstraints<double>    constraints;
    std::vector<dealii::LinearAlgebra::distributed::Vector<double>> nodal;
    dealii::LinearAlgebra::distributed::Vector<double>              weights;
  };

  Manager::Manager(const Parameters              &params,
                   const Mechanics::Problem      &problem,
                   const Geometry::BoundaryNames &names,
                   Logger                        *logger)
    : impl(std::make_unique<Impl>(params, problem, names, logger))
  {}

  Manager::~Manager() = default;

  bool
  Manager::empty() const
  {
    return impl->postprocessors.empty();
  }

  void
  Manager::step(const double               time,
                const unsigned int         beat,
                const double               beat_start,
                const double               cavity_volume,
                const std::optional<bool> &filling,
                std::vector<IO::Column>   &row)
  {
    if (empty())
      return;
    impl->evaluate(time, beat, beat_start, cavity_volume);
    impl->data.filling = filling;
    impl->evaluated    = true;
    for (const auto &p : impl->postprocessors)
      p->step(impl->data, row);
  }

  void
  Manager::end_beat(const std::vector<std::vector<double>> *activation_times,
                    std::vector<IO::Column>                &row)
  {
    if (empty())
      return;
    AssertThrow(impl->evaluated,
                dealii::ExcMessage("Postprocess: end_beat() before step()."));
    for (const auto &p : impl->postprocessors)
      p->end_beat(impl->data, activation_times, row);
  }

  std::vector<double>
  Manager::state() const
  {
    std::vector<double> values;
    for (const auto &p : impl->postprocessors)
      {
        const auto own = p->state();
        values.push_back(static_cast<double>(own.size()));
        values.insert(values.end(), own.begin(), own.end());
      }
    return values;
  }

  void
  Manager::set_state(const std::vector<double> &values)
  {
    std::size_t i = 0;
    for (const auto &p : impl->postprocessors)
      {
        AssertThrow(i < values.size(),
                    dealii::ExcMessage("Postprocess: the saved state has "
                                       "fewer postprocessors than the run."));
        const auto n = static_cast<std::size_t>(values[i++]);
        AssertThrow(i + n <= values.size(),
                    dealii::ExcMessage("Postprocess: the saved state is "
                                       "truncated."));
        p->set_state(
          std::vector<double>(values.begin() + i, values.begin() + i + n));
        i += n;
      }
    AssertThrow(i == values.size(),
                dealii::ExcMessage("Postprocess: the saved state has more "
                                   "postprocessors than the run."));
  }

  void
  Manager::attach_output(dealii::DataOut<3, 3> &data_out)
  {
    if (impl->field_names.empty())
      return;
    AssertThrow(impl->evaluated,
                dealii::ExcMessage(
                  "Postprocess: attach_output() before step()."));
    impl->project();
    for (unsigned int f = 0; f < impl->field_names.size(); ++f)
      data_out.add_data_vector(*impl->dof_handler,
                               impl->nodal[f],
                               impl->field_names[f]);
  }

  std::vector<std::string>
  Manager::field_names() const
  {
    return impl->field_names;
  }

  const std::vector<std::vector<PointQuantities>> &
  Manager::quantities() const
  {
    return impl->quantities;
  }

  const std::vector<std::vector<CardiacFrame>> &
  Manager::frames() const
  {
    return impl->frames;
  }

  std::vector<double>
  Manager::nodal_values(const std::string &name) const
  {
    const auto it =
      std::find(impl->field_names.begin(), impl->field_names.end(), name);
    AssertThrow(it != impl->field_names.end() && !impl->nodal.empty(),
                dealii::ExcMessage("Postprocess: no field '" + name +
                                   "' attached."));
    const auto         &v = impl->nodal[it - impl->field_names.begin()];
    std::vector<double> values;
    for (const auto i : v.locally_owned_elements())
      values.push_back(v(i));
    return values;
  }

  namespace
  {
    /// The value of @p part, which only a postprocessor that needs @p what
    /// sets up (throws otherwise).
    template <class Part>
    const Part &
    needed(const std::optional<Part> &part, const std::string &what)
    {
      AssertThrow(part.has_value(),
                  dealii::ExcMessage(
                    "Postprocess: no postprocessor needs the " + what + "."));
      return *part;
    }
  } // namespace

  const LvWall &
  Manager::wall() const
  {
    return needed(impl->lv_wall, "ventricle");
  }

  const AhaSegments &
  Manager::segments() const
  {
    return needed(impl->aha, "AHA segments");
  }

  std::array<double, 17>
  Manager::segment_volumes() const
  {
    segments();
    std::vector<double> v(impl->segment_volume.begin(),
                          impl->segment_volume.end());
    dealii::Utilities::MPI::sum(v, impl->comm, v);
    std::array<double, 17> result;
    std::copy(v.begin(), v.end(), result.begin());
    return result;
  }

  std::array<unsigned int, 17>
  Manager::segment_cells() const
  {
    segments();
    std::vector<unsigned int> n(impl->segment_count.begin(),
                                impl->segment_count.end());
    dealii::Utilities::MPI::sum(n, impl->comm, n);
    std::array<unsigned int, 17> result;
    std::copy(n.begin(), n.end(), result.begin());
    return result;
  }
} // namespace systole::Postprocess
