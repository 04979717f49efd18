#include "simulation/unloading_parameters.h"

#include "base/units.h"

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
} // namespace systole
