#include "postprocess/factory.h"

#include <deal.II/base/exceptions.h>

#include "postprocess/aha_regional.h"
#include "postprocess/clinical_kinematics.h"
#include "postprocess/fields.h"
#include "postprocess/ventricle_function.h"


namespace systole::Postprocess
{
  namespace
  {
    /// The table line of a postprocessor of point fields: each of @p fields
    /// a name and the value at a point (in the cardiac frame of the wall
    /// coordinates if @p frame).
    PostprocessorRegistry::Entry
    fields_entry(std::string name,
                 std::string description,
                 std::vector<std::pair<std::string, Fields::Getter>> fields,
                 const bool frame = false)
    {
      return {std::move(name),
              std::move(description),
              nullptr,
              [fields, frame] {
                return std::make_unique<Fields>(fields, frame);
              }};
    }

    /// The table line of a postprocessor @p T that has no settings.
    template <class T>
    PostprocessorRegistry::Entry
    entry_of(std::string name, std::string description)
    {
      return {std::move(name), std::move(description), nullptr, [] {
                return std::make_unique<T>();
              }};
    }

  } // namespace

  PostprocessorRegistry &
  postprocessors()
  {
    // The one table of postprocessors (alphabetical).
    static PostprocessorRegistry registry(
      "Postprocess / List of postprocessors",
      {
        entry_of<AhaRegional>(
          "AHA segments",
          "/summary per beat: aha_NN_peak_strain_circumferential, "
          "_longitudinal, _radial and aha_NN_activation_time [ms] of the 17 "
          "AHA segments (NN = 01 ... 17)"),
        fields_entry("active tension",
                     "field active_tension [kPa]",
                     {{"active_tension", &PointQuantities::active_tension}}),
        entry_of<ClinicalKinematics>(
          "clinical kinematics",
          "/timeseries every step, referred to the beat's end-diastole (ED, "
          "the largest cavity volume before ejection): "
          "global_{longitudinal,circumferential,radial}_strain and "
          "endocardial_..._strain (Lagrangian engineering strain in the ED "
          "cardiac frame, wall and inner-third means), twist [deg], "
          "torsion_per_length [deg/mm], av_plane_displacement [mm], "
          "apex_displacement [mm], wall_thickening_ed; /summary per beat: "
          "peak_<column>, end_diastolic_time [ms] and "
          "aha_NN_peak_ed_strain_circumferential, _longitudinal, _radial"),
        fields_entry("fibre stretch",
                     "field fibre_stretch = |F f0| [-]",
                     {{"fibre_stretch", &PointQuantities::fibre_stretch}}),
        fields_entry(
          "strain",
          "fields strain_circumferential, strain_longitudinal, strain_radial: "
          "the Green-Lagrange strain in the cardiac frame of the wall "
          "coordinates [-]",
          {{"strain_circumferential", &PointQuantities::strain_circumferential},
           {"strain_longitudinal", &PointQuantities::strain_longitudinal},
           {"strain_radial", &PointQuantities::strain_radial}},
          true),
        fields_entry(
          "stress",
          "fields first_principal_stress and fibre_stress (Cauchy) [kPa]",
          {{"first_principal_stress", &PointQuantities::first_principal_stress},
           {"fibre_stress", &PointQuantities::fibre_stress}}),
        entry_of<VentricleFunction>(
          "ventricle function",
          "/timeseries every step: long_axis_shortening, wall_thickening, "
          "torsion [deg] (apex to base), ejection_fraction (so far in the "
          "beat)"),
        fields_entry("volume ratio",
                     "field J = det F [-]",
                     {{"J", &PointQuantities::J}}),
      });
    return registry;
  }

  std::vector<std::string>
  postprocessor_names()
  {
    return postprocessors().names();
  }

  std::string
  postprocessor_descriptions()
  {
    std::string text;
    for (const auto &e : postprocessors().all())
      text += std::string(text.empty() ? "" : " ") + "'" + e.name +
              "': " + e.description + ".";
    return text;
  }

  std::unique_ptr<Postprocessor>
  create_postprocessor(const std::string &name)
  {
    return postprocessors().create(name);
  }
} // namespace systole::Postprocess
