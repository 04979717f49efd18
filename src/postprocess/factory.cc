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
    std::unique_ptr<Postprocessor>
    fields(std::vector<std::pair<std::string, Fields::Getter>> f,
           const bool                                          frame = false)
    {
      return std::make_unique<Fields>(std::move(f), frame);
    }

  } // namespace

  PostprocessorRegistry &
  postprocessors()
  {
    // The one table of postprocessors (alphabetical).
    static PostprocessorRegistry registry(
      "Postprocess / List of postprocessors",
      {
        {"AHA segments",
         "/summary per beat: aha_NN_peak_strain_circumferential, "
         "_longitudinal, _radial and aha_NN_activation_time [ms] of the 17 "
         "AHA segments (NN = 01 ... 17)",
         nullptr,
         [] { return std::make_unique<AhaRegional>(); }},
        {"active tension",
         "field active_tension [kPa]",
         nullptr,
         [] {
           return fields({{"active_tension", [](const PointQuantities &q) {
                             return q.active_tension;
                           }}});
         }},
        {"clinical kinematics",
         "/timeseries every step, referred to the beat's end-diastole (ED, "
         "the largest cavity volume before ejection): "
         "global_{longitudinal,circumferential,radial}_strain and "
         "endocardial_..._strain (Lagrangian engineering strain in the ED "
         "cardiac frame, wall and inner-third means), twist [deg], "
         "torsion_per_length [deg/mm], av_plane_displacement [mm], "
         "apex_displacement [mm], wall_thickening_ed; /summary per beat: "
         "peak_<column>, end_diastolic_time [ms] and "
         "aha_NN_peak_ed_strain_circumferential, _longitudinal, _radial",
         nullptr,
         [] { return std::make_unique<ClinicalKinematics>(); }},
        {"fibre stretch",
         "field fibre_stretch = |F f0| [-]",
         nullptr,
         [] {
           return fields({{"fibre_stretch", [](const PointQuantities &q) {
                             return q.fibre_stretch;
                           }}});
         }},
        {"strain",
         "fields strain_circumferential, strain_longitudinal, strain_radial: "
         "the Green-Lagrange strain in the cardiac frame of the wall "
         "coordinates [-]",
         nullptr,
         [] {
           return fields(
             {{"strain_circumferential",
               [](const PointQuantities &q) {
                 return q.strain_circumferential;
               }},
              {"strain_longitudinal",
               [](const PointQuantities &q) { return q.strain_longitudinal; }},
              {"strain_radial",
               [](const PointQuantities &q) { return q.strain_radial; }}},
             true);
         }},
        {"stress",
         "fields first_principal_stress and fibre_stress (Cauchy) [kPa]",
         nullptr,
         [] {
           return fields({{"first_principal_stress",
                           [](const PointQuantities &q) {
                             return q.first_principal_stress;
                           }},
                          {"fibre_stress", [](const PointQuantities &q) {
                             return q.fibre_stress;
                           }}});
         }},
        {"ventricle function",
         "/timeseries every step: long_axis_shortening, wall_thickening, "
         "torsion [deg] (apex to base), ejection_fraction (so far in the "
         "beat)",
         nullptr,
         [] { return std::make_unique<VentricleFunction>(); }},
        {"volume ratio",
         "field J = det F [-]",
         nullptr,
         [] {
           return fields({{"J", [](const PointQuantities &q) { return q.J; }}});
         }},
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
