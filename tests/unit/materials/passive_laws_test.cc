// Checks shared by every passive law and by the volumetric law (STYLE.md
// 2.9): energy and stress zero at F = I; S against central differences of
// psi and the tangent against central differences of S, in E, with the
// observed order checked (about 2); objectivity; major symmetry of the
// tangent; plus the law-specific facts (volumetric
// U(1) = U'(1) = 0, U''(1) = kappa; the tension switches of Holzapfel-Ogden
// and Fung anisotropic; the transversely isotropic reduction of
// Holzapfel-Ogden; Fung anisotropic against Holzapfel-Ogden and Fung
// isotropic; the small-strain shear moduli; the active stress). The laws
// come from the factory table through test_support::passive_law_cases().
//
// Finite differences perturb the Green-Lagrange strain E exactly, through
// test_support::perturb_green_lagrange (F' = F R^{-1} R' with R, R' the
// Cholesky factors of C and C + 2 dE; see support/finite_differences.h).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include "materials/active_stress.h"
#include "materials/fung_anisotropic.h"
#include "materials/fung_isotropic.h"
#include "materials/guccione.h"
#include "materials/holzapfel_ogden.h"
#include "materials/isochoric_part.h"
#include "materials/mooney_rivlin.h"
#include "materials/neo_hookean.h"
#include "materials/veronda_westman.h"
#include "materials/volumetric_law.h"
#include "support/finite_differences.h"
#include "support/law_parameters.h"
#include "support/random_tensors.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace systole;

namespace
{
  /// Size of the random deformations (stretches of roughly 0.7-1.3).
  constexpr double strain = 0.15;

  /// Seeds of the random states (F and fibre frame) of every check. Chosen
  /// so that I4f - 1 and I4s - 1 stay clear of the Holzapfel-Ogden tension
  /// switch during the central differences (checked by
  /// require_clear_of_tension_switch), with fibre and sheet each stretched
  /// in some states and compressed in others (J from 0.76 to 1.27).
  const std::vector<unsigned int> seeds = {2, 4, 11, 13, 14, 17};

  /// Step sizes in E for the central differences: large enough that the
  /// truncation error (not round-off) dominates at all three.
  const std::vector<double> steps = {1e-2, 5e-3, 2.5e-3};

  /// A relative FD error below this is round-off: the derivative is right
  /// and no order can be observed (e.g. St Venant-Kirchhoff, where psi is
  /// quadratic in E and central differences are exact).
  constexpr double round_off = 1e-10;

  /// Accepted deviation of the observed order from 2.
  constexpr double order_margin = 0.25;

  /// A law under test: a case of test_support::passive_law_cases(), or the
  /// isochoric part of one.
  struct LawCase
  {
    std::string                                  name;
    std::shared_ptr<const Materials::PassiveLaw> law;
    std::vector<test_support::TensionSwitch>     tension_switches;
    /// The law is evaluated at F J^(-1/3) (the isochoric part of a law).
    bool isochoric = false;
  };

  /// The isochoric part of a law it owns (IsochoricPart keeps a reference).
  class OwnedIsochoricPart : public Materials::PassiveLaw
  {
  public:
    explicit OwnedIsochoricPart(
      std::shared_ptr<const Materials::PassiveLaw> law)
      : law(std::move(law))
      , part(*this->law)
    {}

    void
    evaluate(const Materials::PassiveInput &in,
             Materials::PassiveOutput      &out) const override
    {
      part.evaluate(in, out);
    }

    std::string
    name() const override
    {
      return part.name();
    }

  private:
    std::shared_ptr<const Materials::PassiveLaw> law;
    Materials::IsochoricPart                     part;
  };

  /// Every law of the factory table with its test parameter sets
  /// (test_support::passive_law_cases(): the defaults, the transversely
  /// isotropic reduction of Holzapfel-Ogden, ...), and the isochoric part of
  /// each (what the mixed formulations use), so that every check below
  /// covers them too.
  std::vector<LawCase>
  passive_laws()
  {
    std::vector<LawCase> laws, parts;
    for (const test_support::LawCase &c : test_support::passive_law_cases())
      {
        laws.push_back({c.label, c.law, c.tension_switches, false});
        parts.push_back({c.label + " (isochoric part)",
                         std::make_shared<OwnedIsochoricPart>(c.law),
                         c.tension_switches,
                         true});
      }
    laws.insert(laws.end(), parts.begin(), parts.end());
    return laws;
  }

  /// psi = U(J), S = S_vol, dS/dE of the volumetric law alone, through
  /// add_to(F, PassiveOutput &) on a zeroed output.
  test_support::MaterialEvaluator
  volumetric_evaluator(const Materials::VolumetricLaw &law)
  {
    return
      [law](const Materials::PassiveInput &in, Materials::PassiveOutput &out) {
        out = Materials::PassiveOutput();
        law.add_to(in.F, out);
      };
  }

  const std::vector<Materials::VolumetricLaw::Form> volumetric_forms = {
    Materials::VolumetricLaw::Form::quadratic,
    Materials::VolumetricLaw::Form::logarithmic,
    Materials::VolumetricLaw::Form::simo_taylor};

  /// Each consecutive pair of steps must show order 2 (within order_margin),
  /// unless the error at the smaller step is already at round-off.
  void
  check_second_order(const test_support::FdStudy &study)
  {
    INFO(study.describe());
    const std::vector<double> orders = study.observed_orders();
    for (unsigned int k = 0; k < orders.size(); ++k)
      if (study.errors[k + 1] < round_off)
        SUCCEED("FD error at round-off: the derivative is exact");
      else
        CHECK(orders[k] == Approx(2.0).margin(order_margin));
  }

  /// Distance of I4 - 1 of @p axis from the blend interval [0, delta] of the
  /// Holzapfel-Ogden tension switch (negative inside it).
  double
  distance_from_switch(const Materials::PassiveInput &in,
                       const dealii::Tensor<1, 3>    &axis,
                       const double                   delta)
  {
    const dealii::Tensor<1, 3> Fa = in.F * axis;
    const double               x  = Fa * Fa - 1.0;
    return std::max(-x, x - delta);
  }

  /// For a law with a tension switch (Holzapfel-Ogden, Fung anisotropic):
  /// the central differences must not cross its blend, where the energy is
  /// only C^2 (a step h in E moves I4 by at most 2h). Other laws are smooth
  /// everywhere. The states are chosen clear of the blend for the full laws
  /// (REQUIREd); the isochoric part evaluates its law at F J^(-1/3), so it
  /// checks that point instead and skips (returns false for) a random state
  /// whose scaled invariants fall into the blend.
  bool
  require_clear_of_tension_switch(const LawCase                 &c,
                                  const Materials::PassiveInput &in)
  {
    Materials::PassiveInput at = in;
    if (c.isochoric)
      at.F *= std::cbrt(1.0 / dealii::determinant(in.F));
    const double needed = 2.0 * steps.front() + 1e-3;
    for (const test_support::TensionSwitch &w : c.tension_switches)
      {
        const double distance =
          distance_from_switch(at, at.basis.*(w.axis), w.width);
        if (c.isochoric && distance <= needed)
          return false;
        INFO("I4 - 1 must stay outside [0, " << w.width
                                             << "] within the FD steps");
        REQUIRE(distance > needed);
      }
    return true;
  }

  /// F0 (I + (alpha_f - 1) f x f)(I + (alpha_s - 1) s x s), scaled so that
  /// I4f - 1 = @p x_f and I4s - 1 = @p x_s (F f and F s are F0 f and F0 s
  /// rescaled, since f and s are orthogonal).
  Materials::PassiveInput
  input_with_fibre_invariants(const unsigned int seed,
                              const double       x_f,
                              const double       x_s)
  {
    Materials::PassiveInput in = test_support::random_passive_input(seed, 0.1);
    const dealii::Tensor<1, 3> Ff      = in.F * in.basis.f;
    const dealii::Tensor<1, 3> Fs      = in.F * in.basis.s;
    const double               alpha_f = std::sqrt((1.0 + x_f) / (Ff * Ff));
    const double               alpha_s = std::sqrt((1.0 + x_s) / (Fs * Fs));
    const dealii::Tensor<2, 3> I(dealii::unit_symmetric_tensor<3>());
    in.F =
      in.F *
      (I + (alpha_f - 1.0) * dealii::outer_product(in.basis.f, in.basis.f)) *
      (I + (alpha_s - 1.0) * dealii::outer_product(in.basis.s, in.basis.s));
    return in;
  }

  /// max |T_ijkl - T_klij| over all indices.
  double
  major_asymmetry(const dealii::SymmetricTensor<4, 3> &T)
  {
    double worst = 0.0;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = 0; l < 3; ++l)
            worst = std::max(worst, std::abs(T[i][j][k][l] - T[k][l][i][j]));
    return worst;
  }

  /// The outputs of two evaluations agree to a relative @p tolerance.
  void
  check_same_output(const Materials::PassiveOutput &a,
                    const Materials::PassiveOutput &b,
                    const double                    tolerance)
  {
    CHECK(a.psi == Approx(b.psi).epsilon(tolerance).margin(1e-300));
    CHECK((a.S - b.S).norm() <= tolerance * b.S.norm());
    CHECK((a.dS_dE - b.dS_dE).norm() <= tolerance * b.dS_dE.norm());
  }
} // namespace


TEST_CASE("Every passive law has zero energy and stress at F = I",
          "[materials]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("fibre frame seed " << seed);
          Materials::PassiveOutput out;
          c.law->evaluate(test_support::identity_input(seed), out);
          CHECK(out.psi == Approx(0.0).margin(1e-14));
          CHECK(out.S.norm() == Approx(0.0).margin(1e-12));
          // The reference tangent is positive on every strain direction.
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int j = i; j < 3; ++j)
              {
                const auto D = test_support::strain_direction(i, j);
                CHECK(D * out.dS_dE * D > 0.0);
              }
        }
    }
}


TEST_CASE("Every passive law's stress is the derivative of its energy",
          "[materials][fd]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("seed " << seed);
          const auto in = test_support::random_passive_input(seed, strain);
          if (!require_clear_of_tension_switch(c, in))
            continue;
          check_second_order(
            test_support::fd_study_of_stress(test_support::evaluator_of(*c.law),
                                             in,
                                             steps));
        }
    }
}


TEST_CASE("Every passive law's tangent is the derivative of its stress",
          "[materials][fd]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("seed " << seed);
          const auto in = test_support::random_passive_input(seed, strain);
          if (!require_clear_of_tension_switch(c, in))
            continue;
          check_second_order(test_support::fd_study_of_tangent(
            test_support::evaluator_of(*c.law),
            in,
            steps));
        }
    }
}


TEST_CASE("Every passive law without its tangent returns the same energy "
          "and stress",
          "[materials]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("state seed " << seed);
          auto in = test_support::random_passive_input(seed, strain);
          Materials::PassiveOutput with, without;
          c.law->evaluate(in, with);
          in.with_tangent = false;
          c.law->evaluate(in, without);
          CHECK(without.psi == with.psi);
          CHECK((without.S - with.S).norm() == 0.0);
        }
    }
}


TEST_CASE("Every passive law is objective", "[materials][objectivity]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("seed " << seed);
          const auto in = test_support::random_passive_input(seed, strain);
          Materials::PassiveInput rotated = in;
          rotated.F = test_support::random_rotation(seed + 500) * in.F;

          Materials::PassiveOutput out, out_rotated;
          c.law->evaluate(in, out);
          c.law->evaluate(rotated, out_rotated);
          check_same_output(out_rotated, out, 1e-10);
        }
    }
}


TEST_CASE("Every passive law has a tangent with major symmetry",
          "[materials][symmetry]")
{
  for (const LawCase &c : passive_laws())
    DYNAMIC_SECTION(c.name)
    {
      for (const unsigned int seed : seeds)
        {
          INFO("seed " << seed);
          Materials::PassiveOutput out;
          c.law->evaluate(test_support::random_passive_input(seed, strain),
                          out);
          CHECK(major_asymmetry(out.dS_dE) <= 1e-14 * out.dS_dE.norm());
        }
    }
}


TEST_CASE("The random states exercise both branches of the Holzapfel-Ogden "
          "tension switch",
          "[materials]")
{
  // Guards the FD cases above: they are only meaningful for Holzapfel-Ogden
  // if some fibres and sheets are stretched and some compressed.
  unsigned int fibres_stretched = 0, sheets_stretched = 0;
  for (const unsigned int seed : seeds)
    {
      const auto in = test_support::random_passive_input(seed, strain);
      fibres_stretched += ((in.F * in.basis.f).norm_square() > 1.0);
      sheets_stretched += ((in.F * in.basis.s).norm_square() > 1.0);
    }
  CHECK(fibres_stretched > 0);
  CHECK(fibres_stretched < seeds.size());
  CHECK(sheets_stretched > 0);
  CHECK(sheets_stretched < seeds.size());
}


TEST_CASE("Every passive law with a tension switch has a consistent "
          "tangent inside the switch",
          "[materials][fd]")
{
  // I4f - 1 and I4s - 1 inside the blend interval [0, delta]: the steps must
  // keep them inside (2h well below the distance to its ends), and the
  // smootherstep's large higher derivatives (~ delta^-3) need small steps
  // for the truncation error to be asymptotic. The laws with a switch
  // (Holzapfel-Ogden, Fung anisotropic) come from the factory table.
  const std::vector<double> small_steps = {4e-5, 2e-5, 1e-5};
  unsigned int              n_laws      = 0;
  for (const test_support::LawCase &c : test_support::passive_law_cases())
    {
      if (c.tension_switches.empty() || c.tension_switches[0].width <= 0.0)
        continue;
      ++n_laws;
      const double delta = c.tension_switches[0].width;
      for (const test_support::TensionSwitch &w : c.tension_switches)
        REQUIRE(w.width == delta); // one blend interval for both axes
      DYNAMIC_SECTION(c.label)
      {
        for (const unsigned int seed : {1u, 2u, 3u})
          {
            INFO("seed " << seed);
            const auto in =
              input_with_fibre_invariants(seed, 0.35 * delta, 0.6 * delta);
            check_second_order(test_support::fd_study_of_stress(
              test_support::evaluator_of(*c.law),
              in,
              small_steps));
            check_second_order(test_support::fd_study_of_tangent(
              test_support::evaluator_of(*c.law),
              in,
              small_steps));
          }
      }
    }
  CHECK(n_laws >= 2); // the check must not become empty
}


TEST_CASE("The Holzapfel-Ogden tension switch is C2 with consistent "
          "derivatives",
          "[materials]")
{
  using Materials::HolzapfelOgden;
  const double delta = 0.01;

  // Off for x <= 0, on for x >= delta, and the blend joins both with zero
  // first and second derivatives.
  for (const double x : {-0.5, -1e-3, 0.0})
    {
      const auto w = HolzapfelOgden::tension_switch(x, delta);
      CHECK(w[0] == 0.0);
      CHECK(w[1] == 0.0);
      CHECK(w[2] == 0.0);
    }
  for (const double x : {delta, 2 * delta, 1.0})
    {
      const auto w = HolzapfelOgden::tension_switch(x, delta);
      CHECK(w[0] == 1.0);
      CHECK(w[1] == 0.0);
      CHECK(w[2] == 0.0);
    }
  const double tiny       = 1e-9 * delta;
  const auto   just_above = HolzapfelOgden::tension_switch(tiny, delta);
  const auto   just_below = HolzapfelOgden::tension_switch(delta - tiny, delta);
  CHECK(just_above[0] == Approx(0.0).margin(1e-12));
  CHECK(just_above[1] * delta == Approx(0.0).margin(1e-12));
  CHECK(just_above[2] * delta * delta == Approx(0.0).margin(1e-6));
  CHECK(just_below[0] == Approx(1.0).margin(1e-12));
  CHECK(just_below[1] * delta == Approx(0.0).margin(1e-12));
  CHECK(just_below[2] * delta * delta == Approx(0.0).margin(1e-6));
  CHECK(HolzapfelOgden::tension_switch(0.5 * delta, delta)[0] ==
        Approx(0.5).epsilon(1e-14));

  // w' and w'' against central differences inside the blend.
  for (const double t : {0.2, 0.45, 0.8}) // w'' = 0 at t = 1/2
    {
      INFO("t = " << t);
      const double          x = t * delta;
      const auto            w = HolzapfelOgden::tension_switch(x, delta);
      test_support::FdStudy first, second;
      for (const double h : {1e-4 * delta, 5e-5 * delta, 2.5e-5 * delta})
        {
          const auto plus  = HolzapfelOgden::tension_switch(x + h, delta);
          const auto minus = HolzapfelOgden::tension_switch(x - h, delta);
          first.steps.push_back(h);
          second.steps.push_back(h);
          first.errors.push_back(
            std::abs((plus[0] - minus[0]) / (2 * h) - w[1]) / std::abs(w[1]));
          second.errors.push_back(
            std::abs((plus[1] - minus[1]) / (2 * h) - w[2]) / std::abs(w[2]));
        }
      check_second_order(first);
      check_second_order(second);
    }
}


TEST_CASE("The transversely isotropic Holzapfel-Ogden law ignores the sheet "
          "direction",
          "[materials]")
{
  // Rotating (s0, n0) about f0 must not change the transversely isotropic
  // law, and must change the orthotropic one (a sanity check of the test).
  const Materials::HolzapfelOgden ti(
    test_support::transversely_isotropic_holzapfel_ogden());
  const Materials::HolzapfelOgden orthotropic{
    Materials::HolzapfelOgden::Parameters()};

  for (const unsigned int seed : seeds)
    {
      INFO("seed " << seed);
      const auto   in    = test_support::random_passive_input(seed, strain);
      auto         spun  = in;
      const double angle = 0.7;
      spun.basis.s =
        std::cos(angle) * in.basis.s + std::sin(angle) * in.basis.n;
      spun.basis.n = dealii::cross_product_3d(spun.basis.f, spun.basis.s);

      Materials::PassiveOutput out, out_spun;
      ti.evaluate(in, out);
      ti.evaluate(spun, out_spun);
      check_same_output(out_spun, out, 1e-12);

      orthotropic.evaluate(in, out);
      orthotropic.evaluate(spun, out_spun);
      CHECK((out_spun.S - out.S).norm() > 1e-6 * out.S.norm());
    }
}


TEST_CASE("Mooney-Rivlin with c2 = 0 is neo-Hookean with mu = 2 c1",
          "[materials]")
{
  Materials::MooneyRivlin::Parameters mr;
  mr.c1 = 3.0;
  mr.c2 = 0.0;
  Materials::NeoHookean::Parameters nh;
  nh.mu = 6.0;
  const Materials::MooneyRivlin mooney_rivlin(mr);
  const Materials::NeoHookean   neo_hookean(nh);
  for (const unsigned int seed : seeds)
    {
      INFO("seed " << seed);
      const auto in = test_support::random_passive_input(seed, strain);
      Materials::PassiveOutput a, b;
      mooney_rivlin.evaluate(in, a);
      neo_hookean.evaluate(in, b);
      check_same_output(a, b, 1e-12);
    }
}


TEST_CASE("Fung anisotropic is Holzapfel-Ogden with a = mu gamma, b = gamma, "
          "a_f = k1, b_f = k2 and no sheet terms",
          "[materials]")
{
  // Two independent implementations of the same energy: mu/2 (e^{gamma x}
  // - 1) = a/(2b) (e^{b x} - 1) for a = mu gamma, b = gamma, and the same
  // tension-switched fibre term.
  Materials::FungAnisotropic::Parameters fung;
  fung.mu    = 3.0;
  fung.gamma = 2.5;
  fung.k1    = 7.0;
  fung.k2    = 4.0;
  Materials::HolzapfelOgden::Parameters ho;
  ho.a    = fung.mu * fung.gamma;
  ho.b    = fung.gamma;
  ho.a_f  = fung.k1;
  ho.b_f  = fung.k2;
  ho.a_s  = 0.0;
  ho.a_fs = 0.0;
  const Materials::FungAnisotropic fung_law(fung);
  const Materials::HolzapfelOgden  ho_law(ho);
  const double                     delta = fung.switch_width;
  for (const unsigned int seed : seeds)
    for (const double x_f : {-0.1, 0.4 * delta, 0.15})
      {
        INFO("seed " << seed << ", I4f - 1 = " << x_f);
        const auto in = input_with_fibre_invariants(seed, x_f, 0.05);
        Materials::PassiveOutput a, b;
        fung_law.evaluate(in, a);
        ho_law.evaluate(in, b);
        check_same_output(a, b, 1e-12);
      }
}


TEST_CASE("Fung anisotropic is Fung isotropic with a compressed fibre or "
          "with k1 = 0",
          "[materials]")
{
  const Materials::FungAnisotropic::Parameters fung;
  Materials::FungAnisotropic::Parameters       no_fibres = fung;
  no_fibres.k1                                           = 0.0;
  Materials::FungIsotropic::Parameters matrix;
  matrix.mu    = fung.mu;
  matrix.gamma = fung.gamma;
  const Materials::FungAnisotropic law(fung), law_without_fibres(no_fibres);
  const Materials::FungIsotropic   isotropic(matrix);
  for (const unsigned int seed : seeds)
    {
      INFO("seed " << seed);
      // A compressed fibre (I4f < 1) carries no fibre stress at all.
      const auto compressed = input_with_fibre_invariants(seed, -0.08, 0.1);
      Materials::PassiveOutput a, b;
      law.evaluate(compressed, a);
      isotropic.evaluate(compressed, b);
      check_same_output(a, b, 1e-14);

      const auto in = test_support::random_passive_input(seed, strain);
      law_without_fibres.evaluate(in, a);
      isotropic.evaluate(in, b);
      check_same_output(a, b, 1e-14);

      // A stretched fibre does (the check above is not vacuous).
      const auto stretched = input_with_fibre_invariants(seed, 0.08, 0.1);
      law.evaluate(stretched, a);
      isotropic.evaluate(stretched, b);
      CHECK(a.psi > b.psi);
      const dealii::Tensor<1, 3> f = stretched.basis.f;
      CHECK(f * ((a.S - b.S) * f) > 0.0);
    }
}


TEST_CASE("Each isotropic law has the small-strain shear modulus its "
          "documentation states",
          "[materials]")
{
  // At F = I an isotropic law linearizes to S = lambda tr(E) I + 2 mu0 E; an
  // isochoric one to dS/dE = 2 mu0 (II - I x I / 3). The parameter sets are
  // those of the verification table (scripts/bench.py, group "laws": the
  // shear modulus 5 kPa of the isotropic Guccione law of Land problem 2).
  using namespace Materials;
  const double                        mu0 = 5.0;
  const dealii::SymmetricTensor<2, 3> I   = dealii::unit_symmetric_tensor<3>();
  const dealii::SymmetricTensor<4, 3> deviatoric =
    2.0 * mu0 *
    (dealii::identity_tensor<3>() - (1.0 / 3.0) * dealii::outer_product(I, I));

  NeoHookean::Parameters nh;
  nh.mu = mu0;
  MooneyRivlin::Parameters mr;
  mr.c1 = 2.0;
  mr.c2 = 0.5; // 2 (c1 + c2) = 5
  FungIsotropic::Parameters fung;
  fung.mu    = 10.0;
  fung.gamma = 0.5; // mu gamma = 5
  VerondaWestman::Parameters vw;
  vw.c1    = 10.0;
  vw.gamma = 0.5; // c1 gamma = 5
  FungAnisotropic::Parameters fung_anisotropic;
  fung_anisotropic.mu    = 10.0;
  fung_anisotropic.gamma = 0.5; // across the fibres as Fung isotropic
  const std::vector<std::pair<std::string, std::shared_ptr<PassiveLaw>>>
    isochoric = {
      {"neo-Hookean", std::make_shared<NeoHookean>(nh)},
      {"Mooney-Rivlin", std::make_shared<MooneyRivlin>(mr)},
      {"Fung isotropic", std::make_shared<FungIsotropic>(fung)},
      {"Veronda-Westman", std::make_shared<VerondaWestman>(vw)},
      {"Fung anisotropic", std::make_shared<FungAnisotropic>(fung_anisotropic)},
    };
  for (const auto &[name, law] : isochoric)
    DYNAMIC_SECTION(name)
    {
      PassiveOutput out;
      law->evaluate(test_support::identity_input(3), out);
      CHECK((out.dS_dE - deviatoric).norm() <= 1e-13 * deviatoric.norm());
    }

  SECTION("Guccione, isotropic (b_f = b_t = b_fs = 1): mu0 = C/2, lambda = 0")
  {
    Guccione::Parameters g;
    g.C    = 2.0 * mu0;
    g.b_f  = 1.0;
    g.b_t  = 1.0;
    g.b_fs = 1.0;
    const Guccione law(g);
    PassiveOutput  out;
    law.evaluate(test_support::identity_input(3), out);
    const dealii::SymmetricTensor<4, 3> expected =
      2.0 * mu0 * dealii::identity_tensor<3>();
    CHECK((out.dS_dE - expected).norm() <= 1e-13 * expected.norm());
  }
}


TEST_CASE("Every volumetric form has U(1) = U'(1) = 0 and U''(1) = kappa",
          "[materials][volumetric]")
{
  const double kappa = 350.0;
  for (const auto form : volumetric_forms)
    DYNAMIC_SECTION(Materials::VolumetricLaw::name_of(form))
    {
      const Materials::VolumetricLaw law(form, kappa);
      CHECK(law.energy(1.0) == Approx(0.0).margin(1e-14 * kappa));
      CHECK(law.first_derivative(1.0) == Approx(0.0).margin(1e-14 * kappa));
      CHECK(law.second_derivative(1.0) == Approx(kappa).epsilon(1e-14));

      // Energy, stress and tangent are also zero/kappa at F = I.
      Materials::PassiveOutput out;
      law.add_to(test_support::identity_input().F, out);
      CHECK(out.psi == Approx(0.0).margin(1e-14 * kappa));
      CHECK(out.S.norm() == Approx(0.0).margin(1e-12 * kappa));
      const dealii::SymmetricTensor<2, 3> I =
        dealii::unit_symmetric_tensor<3>();
      CHECK((out.dS_dE - kappa * dealii::outer_product(I, I)).norm() <=
            1e-14 * kappa);

      // U' and U'' are the derivatives of U (central differences in J).
      for (const double J : {0.8, 1.05, 1.3})
        {
          INFO("J = " << J);
          test_support::FdStudy first, second;
          for (const double h : {1e-2, 5e-3, 2.5e-3})
            {
              first.steps.push_back(h);
              second.steps.push_back(h);
              first.errors.push_back(
                std::abs((law.energy(J + h) - law.energy(J - h)) / (2 * h) -
                         law.first_derivative(J)) /
                std::abs(law.first_derivative(J)));
              second.errors.push_back(std::abs((law.first_derivative(J + h) -
                                                law.first_derivative(J - h)) /
                                                 (2 * h) -
                                               law.second_derivative(J)) /
                                      std::abs(law.second_derivative(J)));
            }
          check_second_order(first);
          check_second_order(second);
        }
    }
}


TEST_CASE("The volumetric stress and tangent are derivatives of the "
          "volumetric energy",
          "[materials][volumetric][fd]")
{
  for (const auto form : volumetric_forms)
    DYNAMIC_SECTION(Materials::VolumetricLaw::name_of(form))
    {
      const Materials::VolumetricLaw law(form, 350.0);
      const auto                     evaluate = volumetric_evaluator(law);
      for (const unsigned int seed : seeds)
        {
          INFO("seed " << seed);
          const auto in = test_support::random_passive_input(seed, strain);
          check_second_order(
            test_support::fd_study_of_stress(evaluate, in, steps));
          check_second_order(
            test_support::fd_study_of_tangent(evaluate, in, steps));

          // Objective and with a major-symmetric tangent, like the passive
          // laws.
          Materials::PassiveInput rotated = in;
          rotated.F = test_support::random_rotation(seed + 500) * in.F;
          Materials::PassiveOutput out, out_rotated;
          evaluate(in, out);
          evaluate(rotated, out_rotated);
          check_same_output(out_rotated, out, 1e-10);
          CHECK(major_asymmetry(out.dS_dE) <= 1e-14 * out.dS_dE.norm());
        }
    }
}


TEST_CASE("The volumetric law adds to a stress and tangent already present",
          "[materials][volumetric]")
{
  const Materials::VolumetricLaw law(
    Materials::VolumetricLaw::Form::logarithmic,
    350.0);
  const Materials::Guccione passive{Materials::Guccione::Parameters()};
  const auto                in = test_support::random_passive_input(7, strain);

  Materials::PassiveOutput alone;
  law.add_to(in.F, alone);
  CHECK(alone.psi == Approx(law.energy(dealii::determinant(in.F))));

  Materials::PassiveOutput total;
  passive.evaluate(in, total);
  const Materials::PassiveOutput passive_only = total;
  law.add_to(in.F, total);
  CHECK(total.psi == Approx(passive_only.psi + alone.psi).epsilon(1e-14));
  CHECK((total.S - passive_only.S - alone.S).norm() <= 1e-13 * total.S.norm());
  CHECK((total.dS_dE - passive_only.dS_dE - alone.dS_dE).norm() <=
        1e-13 * total.dS_dE.norm());

  // The three-argument overload adds the same stress and tangent.
  dealii::SymmetricTensor<2, 3> S     = passive_only.S;
  dealii::SymmetricTensor<4, 3> dS_dE = passive_only.dS_dE;
  law.add_to(in.F, S, dS_dE);
  CHECK((S - total.S).norm() <= 1e-14 * total.S.norm());
  CHECK((dS_dE - total.dS_dE).norm() <= 1e-14 * total.dS_dE.norm());

  // S_vol = J U'(J) C^{-1}.
  const double                        J = dealii::determinant(in.F);
  const dealii::SymmetricTensor<2, 3> C_inv =
    dealii::invert(dealii::symmetrize(dealii::transpose(in.F) * in.F));
  CHECK((alone.S - J * law.first_derivative(J) * C_inv).norm() <=
        1e-13 * alone.S.norm());
}


TEST_CASE("The volumetric law rejects a non-positive volume ratio",
          "[materials][volumetric]")
{
  dealii::Tensor<2, 3> inverted(dealii::unit_symmetric_tensor<3>());
  inverted[0][0] = -1.0;
  for (const auto form : volumetric_forms)
    DYNAMIC_SECTION(Materials::VolumetricLaw::name_of(form))
    {
      const Materials::VolumetricLaw law(form, 350.0);
      Materials::PassiveOutput       out;
      CHECK_THROWS_AS(law.add_to(inverted, out),
                      Materials::ExcNonPositiveVolumeRatio);
      CHECK_THROWS_AS(law.energy(0.0), Materials::ExcNonPositiveVolumeRatio);
    }
}


TEST_CASE("Active stress adds T_a f0 x f0 plus the sheet and normal "
          "fractions of T_a across the fibres",
          "[materials][active]")
{
  const double Ta = 7.5;
  for (const unsigned int seed : seeds)
    for (const auto &[eta_s, eta_n] :
         std::vector<std::pair<double, double>>{{0.0, 0.0},
                                                {0.3, 0.3},
                                                {0.4, 0.1},
                                                {0.0, 1.0}})
      {
        INFO("seed " << seed << ", sheet " << eta_s << ", normal " << eta_n);
        const Fibres::FibreBasis basis = test_support::random_fibre_basis(seed);
        const auto start = test_support::random_passive_input(seed, strain).F;
        const dealii::SymmetricTensor<2, 3> S0 =
          dealii::symmetrize(start + dealii::transpose(start));

        dealii::SymmetricTensor<2, 3> S = S0;
        Materials::add_active_stress(Ta, {eta_s, eta_n}, basis, S);

        // Against the formula, entry by entry.
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            {
              const double expected =
                S0[i][j] + Ta * (basis.f[i] * basis.f[j] +
                                 eta_s * basis.s[i] * basis.s[j] +
                                 eta_n * basis.n[i] * basis.n[j]);
              CHECK(S[i][j] == Approx(expected).epsilon(1e-14).margin(1e-14));
            }

        // In the fibre frame: T_a along f, eta_s T_a along s, eta_n T_a
        // along n, no shear.
        const dealii::SymmetricTensor<2, 3> dS = S - S0;
        CHECK(basis.f * (dS * basis.f) == Approx(Ta).epsilon(1e-13));
        CHECK(basis.s * (dS * basis.s) ==
              Approx(eta_s * Ta).epsilon(1e-13).margin(1e-13));
        CHECK(basis.n * (dS * basis.n) ==
              Approx(eta_n * Ta).epsilon(1e-13).margin(1e-13));
        CHECK(basis.f * (dS * basis.s) == Approx(0.0).margin(1e-13));
        CHECK(basis.f * (dS * basis.n) == Approx(0.0).margin(1e-13));
        CHECK(basis.s * (dS * basis.n) == Approx(0.0).margin(1e-13));
      }
}


TEST_CASE("Active stress rejects a cross-fibre fraction outside [0, 1]",
          "[materials][active]")
{
  const Fibres::FibreBasis      basis = test_support::random_fibre_basis(3);
  dealii::SymmetricTensor<2, 3> S;
  for (const double eta : {-0.1, -1e-12, 1.0 + 1e-12, 1.5})
    {
      INFO("fraction " << eta);
      CHECK_THROWS_AS(Materials::add_active_stress(5.0, {eta, 0.0}, basis, S),
                      dealii::ExceptionBase);
      CHECK_THROWS_AS(Materials::add_active_stress(5.0, {0.0, eta}, basis, S),
                      dealii::ExceptionBase);
      CHECK(S.norm() == 0.0); // nothing was added before the throw
    }
  CHECK_NOTHROW(Materials::add_active_stress(5.0, {0.0, 0.0}, basis, S));
  CHECK_NOTHROW(Materials::add_active_stress(5.0, {1.0, 1.0}, basis, S));
}


TEST_CASE("The logistic tension switch of Arostica et al. 2025: values, "
          "derivatives and the FD tangent across I4 = 1",
          "[materials][fd]")
{
  using Materials::HolzapfelOgden;
  const double k = 100.0;
  // w = 1/(1 + e^{-k x}) directly (the law uses the tanh form).
  for (const double x : {-0.3, -0.02, -1e-3, 0.0, 1e-3, 0.02, 0.3})
    {
      const auto   w     = HolzapfelOgden::logistic_switch(x, k);
      const double plain = 1.0 / (1.0 + std::exp(-k * x));
      CHECK(w[0] == Approx(plain).epsilon(1e-13).margin(1e-300));
      // First and second derivatives against central differences.
      const double h  = 1e-5;
      const auto   wp = HolzapfelOgden::logistic_switch(x + h, k);
      const auto   wm = HolzapfelOgden::logistic_switch(x - h, k);
      CHECK(w[1] ==
            Approx((wp[0] - wm[0]) / (2 * h)).epsilon(1e-6).margin(1e-9));
      CHECK(w[2] ==
            Approx((wp[1] - wm[1]) / (2 * h)).epsilon(1e-6).margin(1e-7));
    }
  CHECK(HolzapfelOgden::logistic_switch(0.0, k)[0] == 0.5);
  // No overflow far in compression or tension.
  CHECK(HolzapfelOgden::logistic_switch(-50.0, 1e3)[0] == 0.0);
  CHECK(HolzapfelOgden::logistic_switch(50.0, 1e3)[0] == 1.0);

  // The law's stress and tangent against central differences with I4f - 1
  // and I4s - 1 on, and on both sides of, the switch (observed order 2).
  const HolzapfelOgden      law(test_support::arostica_holzapfel_ogden());
  const std::vector<double> steps = {4e-5, 2e-5, 1e-5};
  for (const auto &[x_f, x_s] :
       std::vector<std::pair<double, double>>{{0.0, 0.0},
                                              {-0.01, 0.005},
                                              {0.004, -0.02},
                                              {-0.05, -0.05}})
    for (const unsigned int seed : {1u, 2u})
      {
        INFO("I4f - 1 = " << x_f << ", I4s - 1 = " << x_s << ", seed " << seed);
        const auto in = input_with_fibre_invariants(seed, x_f, x_s);
        check_second_order(
          test_support::fd_study_of_stress(test_support::evaluator_of(law),
                                           in,
                                           steps));
        check_second_order(
          test_support::fd_study_of_tangent(test_support::evaluator_of(law),
                                            in,
                                            steps));
      }

  // A compressed fibre keeps the small stress of the logistic weight: at
  // I4f = 0.95 the fibre term is w(-0.05) = 1/(1 + e^5) of the full one.
  HolzapfelOgden::Parameters fibre_only =
    test_support::arostica_holzapfel_ogden();
  fibre_only.a_s = fibre_only.a_fs = 0.0;
  const HolzapfelOgden    switched(fibre_only);
  Materials::PassiveInput in  = input_with_fibre_invariants(3, -0.05, 0.0);
  fibre_only.switch_sharpness = 1e6; // effectively the hard switch: off
  const HolzapfelOgden     off(fibre_only);
  Materials::PassiveOutput a, b;
  switched.evaluate(in, a);
  off.evaluate(in, b);
  const double x = -0.05;
  const double psi =
    0.5 * fibre_only.a_f / fibre_only.b_f * std::expm1(fibre_only.b_f * x * x);
  CHECK(a.psi - b.psi == Approx(psi / (1.0 + std::exp(5.0))).epsilon(1e-9));
}
