#include "support/random_tensors.h"

#include "postprocess/point_quantities.h"
#include <catch2/catch.hpp>

#include <cmath>

using systole::Postprocess::CardiacFrame;
using systole::Postprocess::point_quantities;

namespace
{
  /// A random orthonormal cardiac frame (c, l, r = c x l).
  CardiacFrame
  random_frame(const unsigned int seed)
  {
    const auto   b = test_support::random_fibre_basis(seed);
    CardiacFrame frame;
    frame.circumferential = b.f;
    frame.longitudinal    = b.s;
    frame.radial          = b.n;
    return frame;
  }
} // namespace

TEST_CASE("A stretch along the fibre gives lambda_f, J and the frame strains "
          "in closed form",
          "[postprocess][analytic]")
{
  for (unsigned int seed = 1; seed <= 5; ++seed)
    {
      const auto   basis  = test_support::random_fibre_basis(seed);
      const auto   frame  = random_frame(seed + 100);
      const double lambda = 0.8 + 0.1 * seed;
      // F = I + (lambda - 1) f0 x f0; S = s0 f0 x f0 (a uniaxial stress).
      const dealii::Tensor<2, 3> F =
        dealii::unit_symmetric_tensor<3>() +
        (lambda - 1) * dealii::outer_product(basis.f, basis.f);
      const double s0 = 7.5;
      // sigma = J^-1 F S F^T = lambda s0 f0 x f0 (F f0 = lambda f0, J =
      // lambda).
      const dealii::SymmetricTensor<2, 3> sigma = dealii::symmetrize(
        lambda * s0 * dealii::outer_product(basis.f, basis.f));
      const auto q = point_quantities(F, basis, sigma, 3.0, &frame);
      CHECK(q.fibre_stretch == Approx(lambda).epsilon(1e-12));
      CHECK(q.J == Approx(lambda).epsilon(1e-12));
      CHECK(q.active_tension == 3.0);
      CHECK(q.fibre_stress == Approx(lambda * s0).epsilon(1e-12));
      CHECK(q.first_principal_stress == Approx(lambda * s0).epsilon(1e-12));
      // E = (lambda^2 - 1)/2 f0 x f0: e . E e = (lambda^2 - 1)/2 (f0 . e)^2.
      const double e     = 0.5 * (lambda * lambda - 1);
      const auto   along = [&](const dealii::Tensor<1, 3> &v) {
        return e * (basis.f * v) * (basis.f * v);
      };
      CHECK(std::abs(q.strain_circumferential - along(frame.circumferential)) <
            1e-12);
      CHECK(std::abs(q.strain_longitudinal - along(frame.longitudinal)) <
            1e-12);
      CHECK(std::abs(q.strain_radial - along(frame.radial)) < 1e-12);
    }
}

TEST_CASE("A simple shear in the cardiac frame gives the closed-form strains",
          "[postprocess][analytic]")
{
  const auto frame = random_frame(7);
  const auto basis = test_support::random_fibre_basis(8);
  for (const double gamma : {0.1, 0.3, -0.5})
    {
      // F = I + gamma e_c x e_l: E_cc = 0, E_ll = gamma^2 / 2, E_rr = 0, J = 1.
      const dealii::Tensor<2, 3> F =
        dealii::unit_symmetric_tensor<3>() +
        gamma *
          dealii::outer_product(frame.circumferential, frame.longitudinal);
      const auto q = point_quantities(F,
                                      basis,
                                      dealii::SymmetricTensor<2, 3>(),
                                      0.0,
                                      &frame);
      CHECK(std::abs(q.strain_circumferential) < 1e-14);
      CHECK(std::abs(q.strain_longitudinal - 0.5 * gamma * gamma) < 1e-14);
      CHECK(std::abs(q.strain_radial) < 1e-14);
      CHECK(std::abs(q.J - 1.0) < 1e-14);
      // |F f0|^2 = 1 + 2 gamma (f0.c)(f0.l) + gamma^2 (f0.l)^2.
      const double fc = basis.f * frame.circumferential,
                   fl = basis.f * frame.longitudinal;
      CHECK(q.fibre_stretch ==
            Approx(std::sqrt(1 + 2 * gamma * fc * fl + gamma * gamma * fl * fl))
              .epsilon(1e-13));
    }
}

TEST_CASE("Without a cardiac frame the strains are NaN", "[postprocess]")
{
  const auto q = point_quantities(dealii::unit_symmetric_tensor<3>(),
                                  systole::Fibres::FibreBasis::cartesian(),
                                  dealii::SymmetricTensor<2, 3>(),
                                  0.0,
                                  nullptr);
  CHECK(std::isnan(q.strain_circumferential));
  CHECK(q.fibre_stretch == 1.0);
}
