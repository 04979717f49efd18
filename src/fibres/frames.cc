#include "fibres/frames.h"

#include <deal.II/base/exceptions.h>

#include "geometry/point_location.h"

#include <cmath>

namespace systole::Fibres
{
  void
  validate(const FibreBasis &b, const std::string &where, const double tol)
  {
    const auto bad = [&](const std::string &what) {
      AssertThrow(false,
                  dealii::ExcMessage("The fibre frame at " + where +
                                     " is not valid: " + what + "."));
    };
    for (const auto *v : {&b.f, &b.s, &b.n})
      for (unsigned int d = 0; d < 3; ++d)
        if (!std::isfinite((*v)[d]))
          bad("it has a NaN or infinite component");
    if (std::abs(b.f.norm() - 1) > tol || std::abs(b.s.norm() - 1) > tol ||
        std::abs(b.n.norm() - 1) > tol)
      bad("a direction is not a unit vector");
    if (std::abs(b.f * b.s) > tol || std::abs(b.f * b.n) > tol ||
        std::abs(b.s * b.n) > tol)
      bad("the directions are not orthogonal");
    if ((dealii::cross_product_3d(b.f, b.s) - b.n).norm() > tol)
      bad("it is not right-handed (n != f x s)");
  }

  void
  validated_bases(const std::vector<dealii::Point<3>>           &points,
                  const std::string                             &name,
                  const std::function<FibreBasis(unsigned int)> &basis_at,
                  std::vector<FibreBasis>                       &bases)
  {
    bases.resize(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      {
        bases[i] = basis_at(i);
        validate(bases[i],
                 Geometry::format_point(points[i]) + " (" + name +
                   " generator)");
      }
  }

  double
  helix_angle(const dealii::Tensor<1, 3> &f,
              const dealii::Tensor<1, 3> &e_c,
              const dealii::Tensor<1, 3> &e_l)
  {
    return std::atan2(f * e_l, f * e_c);
  }
} // namespace systole::Fibres
