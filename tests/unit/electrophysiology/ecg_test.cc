// The pseudo-ECG: the lead definitions, the biomarkers of a synthetic beat,
// the lead field of a planar front in a slab against the exact integral and
// the far field of a uniform double layer (hexahedra Q1 and Q2,
// tetrahedra), and the ECG of a monodomain run under mesh refinement.
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>

#include "electrophysiology/ecg.h"
#include "electrophysiology/monodomain.h"
#include "geometry/cell_kind.h"
#include "geometry/distributed_mesh.h"
#include "geometry/mesh.h"
#include "support/ep_fixture.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

using namespace systole;
using namespace systole::Electrophysiology;

namespace
{
  /// The slab [0, 10] x [0, 4] x [0, 2] mm and the front V = -80 + 50 (1 -
  /// tanh((x - x0)/delta)) mV: +20 mV in the activated tissue at x < x0, -80
  /// mV ahead (a front moving towards +x).
  constexpr double Lx = 10, Ly = 4, Lz = 2, x0 = 5;

  double
  front_potential(const double x, const double delta)
  {
    return -80.0 + 50.0 * (1.0 - std::tanh((x - x0) / delta));
  }

  double
  front_derivative(const double x, const double delta)
  {
    const double c = std::cosh((x - x0) / delta);
    return -50.0 / (delta * c * c);
  }

  /// The solid angle (signed with d = x - x_e) of the slab's cross-section
  /// at x seen from @p e: ∫∫ d / r³ dy dz over [0, Ly] x [0, Lz].
  double
  solid_angle(const double x, const dealii::Point<3> &e)
  {
    const double d = x - e[0];
    const auto   F = [d](const double u, const double v) {
      return std::atan(u * v / (d * std::sqrt(u * u + v * v + d * d)));
    };
    const double u1 = -e[1], u2 = Ly - e[1], v1 = -e[2], v2 = Lz - e[2];
    return F(u2, v2) - F(u1, v2) - F(u2, v1) + F(u1, v1);
  }

  /// The exact pseudo-ECG of the front for conductivity @p sigma along x:
  /// σ/(4π σ_b) ∫ V'(x) Ω(x) dx by composite Gauss-Legendre (400 x 10
  /// points), independent of the finite elements.
  double
  exact_potential(const dealii::Point<3> &e,
                  const double            sigma,
                  const double            sigma_b,
                  const double            delta)
  {
    const dealii::QGauss<1> gauss(10);
    const unsigned int      n   = 400;
    double                  sum = 0;
    for (unsigned int k = 0; k < n; ++k)
      for (unsigned int q = 0; q < gauss.size(); ++q)
        {
          const double x = Lx * (k + gauss.point(q)[0]) / n;
          sum += front_derivative(x, delta) * solid_angle(x, e) *
                 gauss.weight(q) * Lx / n;
        }
    return sigma / (4 * M_PI * sigma_b) * sum;
  }

  /// The lead field's potentials of the front on the slab meshed with
  /// @p cells per mm, hexahedra (Q @p degree) or tetrahedra (P1), fibres
  /// along @p fibre.
  std::vector<double>
  lead_field_potentials(const std::vector<dealii::Point<3>> &electrodes,
                        const unsigned int                   cells_per_mm,
                        const unsigned int                   degree,
                        const bool                           tetrahedra,
                        const unsigned int                   fibre,
                        const double                         sigma_l,
                        const double                         sigma_t,
                        const double                         sigma_b,
                        const double                         delta)
  {
    Geometry::Parameters geometry;
    geometry.type       = Geometry::Parameters::Type::box;
    geometry.box_lower  = dealii::Point<3>();
    geometry.box_upper  = dealii::Point<3>(Lx, Ly, Lz);
    geometry.box_cells  = {{static_cast<unsigned int>(Lx) * cells_per_mm,
                            static_cast<unsigned int>(Ly) * cells_per_mm,
                            static_cast<unsigned int>(Lz) * cells_per_mm}};
    geometry.tetrahedra = tetrahedra;
    const auto mesh =
      Geometry::create_distributed_mesh(geometry, MPI_COMM_WORLD);
    const Geometry::CellKind kind(*mesh.tria);
    const auto               mapping = kind.mapping(*mesh.tria, 1);
    const auto               fe      = kind.lagrange(degree);
    dealii::DoFHandler<3>    dofs(*mesh.tria);
    dofs.distribute_dofs(*fe);
    const dealii::Tensor<1, 3> f = test_support::unit_vector(fibre);
    const Fibres::FibreField   fibres =
      [f](const auto &, const auto &points, auto &bases) {
        Fibres::FibreBasis b;
        b.f = f;
        bases.assign(points.size(), b);
      };
    const LeadField lead_field(dofs,
                               *mapping,
                               kind.cell_quadrature(degree + 2),
                               fibres,
                               sigma_l,
                               sigma_t,
                               electrodes,
                               sigma_b);
    // The front at the owned nodes, in the order of the owned DoFs.
    std::map<dealii::types::global_dof_index, dealii::Point<3>> support;
    dealii::DoFTools::map_dofs_to_support_points(*mapping, dofs, support);
    std::vector<double> v;
    for (const auto i : dofs.locally_owned_dofs())
      v.push_back(front_potential(support.at(i)[0], delta));
    return lead_field.potentials(dealii::make_array_view(v));
  }

  /// Electrodes around the slab: ahead of the front on its axis, behind it,
  /// beside it, and far away (50 and 200 mm) obliquely.
  std::vector<dealii::Point<3>>
  slab_electrodes()
  {
    return {dealii::Point<3>(20, 2, 1),
            dealii::Point<3>(-8, 3, 0),
            dealii::Point<3>(7, 12, 1),
            dealii::Point<3>(35, 40, 10),
            dealii::Point<3>(-140, 100, 80)};
  }
} // namespace


TEST_CASE("The 12 leads follow Einthoven, Goldberger and Wilson", "[ecg]")
{
  // RA, LA, LL, V1 ... V6
  const std::vector<double> phi  = {0.3, -0.2, 0.7, 1, 2, 3, 4, 5, 6};
  const auto                lead = leads_from_electrodes(phi);
  const double              wct  = (0.3 - 0.2 + 0.7) / 3;
  CHECK(lead[0] == Approx(-0.5));              // I = LA - RA
  CHECK(lead[1] == Approx(0.4));               // II = LL - RA
  CHECK(lead[2] == Approx(0.9));               // III = LL - LA
  CHECK(lead[0] + lead[2] == Approx(lead[1])); // Einthoven's law
  CHECK(lead[3] == Approx(0.3 - 0.25));        // aVR = RA - (LA + LL)/2
  CHECK(lead[4] == Approx(-0.2 - 0.5));        // aVL
  CHECK(lead[5] == Approx(0.7 - 0.05));        // aVF
  CHECK(lead[3] + lead[4] + lead[5] == Approx(0.0).margin(1e-15));
  for (unsigned int i = 0; i < 6; ++i)
    CHECK(lead[6 + i] == Approx(phi[3 + i] - wct));
  CHECK(lead_names()[3] == "aVR");
  CHECK(lead_names()[11] == "V6");
}


TEST_CASE("The electrode entry names every electrode once", "[ecg]")
{
  const auto e = parse_electrodes(
    "V6: 6 0 0; V5: 5,0,0; V4: 4 0 0; V3: 3 0 0; V2: 2 0 0; V1: 1 0 0; "
    "LL: 0 0 -9; LA: 0 9 0; RA: 0 -9 0");
  REQUIRE(e.size() == 9);
  CHECK(e[0].name == "RA");
  CHECK(e[0].position[1] == -9);
  CHECK(e[4].name == "V2");
  CHECK(e[7].position[0] == 5);
  CHECK_THROWS(parse_electrodes("RA: 0 0 0; LA: 1 0 0"));
  CHECK_THROWS(parse_electrodes(
    "V6: 6 0 0; V5: 5,0,0; V4: 4 0 0; V3: 3 0 0; V2: 2 0 0; V1: 1 0 0; "
    "LL: 0 0 -9; LA: 0 9 0; RA: 0 -9 0; V7: 1 1 1"));
  CHECK_THROWS(parse_electrodes("RA: 0 0"));
}


TEST_CASE("The ECG biomarkers of a synthetic beat", "[ecg]")
{
  // QRS: A_l sin²(π(t − 20)/80) on [20, 100] ms; T: B_l sin²(π(t − 250)/200)
  // on [250, 450] ms. The QRS spans its bump (zero outside: the first
  // deflection after the sample at 20 ms, the J point at 100 ms); the T
  // wave's level θ (its own peak) is crossed where sin² = θ.
  const std::array<double, 12> A = {
    {1.0, 1.5, 0.5, -1.2, 0.2, 1.0, -0.6, -0.3, 0.4, 1.2, 1.4, 1.1}};
  const std::array<double, 12> B = {
    {0.2, 0.3, 0.1, -0.25, 0.05, 0.2, -0.1, 0.1, 0.3, 0.3, 0.25, 0.2}};
  const auto bump = [](const double t, const double a, const double b) {
    return t > a && t < b ? std::pow(std::sin(M_PI * (t - a) / (b - a)), 2)
                          : 0.0;
  };
  std::vector<double>                 times;
  std::vector<std::array<double, 12>> leads;
  for (double t = 0; t <= 600; t += 0.5)
    {
      std::array<double, 12> v;
      for (unsigned int l = 0; l < 12; ++l)
        v[l] = A[l] * bump(t, 20, 100) + B[l] * bump(t, 250, 450);
      times.push_back(t);
      leads.push_back(v);
    }
  const double theta = 0.1;
  const auto   b     = ecg_biomarkers(times, leads, theta);
  const double x     = std::asin(std::sqrt(theta)) / M_PI;
  // Within a sample (0.5 ms): the bump's first and last samples lie below
  // 0.1 % of its peak (sin²(π 0.5/80) = 3.9e-4).
  CHECK(b.qrs_onset == Approx(20.5).margin(1e-12));
  CHECK(b.qrs_end == Approx(99.5).margin(1e-12));
  CHECK(b.t_end == Approx(450 - 200 * x).margin(0.05));
  CHECK(b.qt_interval == Approx(450 - 200 * x - 20.5).margin(0.05));
  for (unsigned int l = 0; l < 12; ++l)
    CHECK(b.r_amplitude[l] == Approx(std::max(A[l], 0.0)).margin(1e-12));

  // A T wave still under way at the last sample: no T end, but a QRS.
  times.resize(700); // up to 349.5 ms
  leads.resize(700);
  const auto cut = ecg_biomarkers(times, leads, theta);
  CHECK(cut.qrs_duration == Approx(b.qrs_duration));
  CHECK(std::isnan(cut.t_end));
  CHECK(std::isnan(cut.qt_interval));
}


TEST_CASE("The QRS spans its small first and last deflections up to the J "
          "point",
          "[ecg]")
{
  // A QRS of three waves on [30, 110] ms: a small first deflection
  // (3 % of the main one: the first junctions) on [30, 50], the main one
  // on [40, 90], a small terminal one (4 %: the last basal cells) on
  // [80, 110]; then a slowly rising ST segment (0.2 % of the main wave per
  // 100 ms, from 110 ms) up to a T wave on [250, 450]. Each wave is a
  // sin² bump of its own lead weights. A threshold at 10 % of the peak
  // sees only the main wave; the QRS is the whole [30, 110].
  const auto bump = [](const double t, const double a, const double b) {
    return t > a && t < b ? std::pow(std::sin(M_PI * (t - a) / (b - a)), 2)
                          : 0.0;
  };
  std::array<double, 12> first, main, last, st;
  for (unsigned int l = 0; l < 12; ++l)
    {
      first[l] = 0.03 * std::cos(0.7 * l);
      main[l]  = std::sin(1.3 * l + 0.4);
      last[l]  = 0.04 * std::cos(2.1 * l + 1);
      st[l]    = 0.3 * std::sin(0.9 * l + 2);
    }
  std::vector<double>                 times;
  std::vector<std::array<double, 12>> leads;
  for (double t = 0; t <= 600; t += 0.5)
    {
      std::array<double, 12> v;
      const double ramp = t > 110 ? std::min(t - 110, 140.0) * 2e-5 : 0.0;
      for (unsigned int l = 0; l < 12; ++l)
        v[l] = first[l] * bump(t, 30, 50) + main[l] * bump(t, 40, 90) +
               last[l] * bump(t, 80, 110) + st[l] * (ramp + bump(t, 250, 450));
      times.push_back(t);
      leads.push_back(v);
    }
  const auto b = ecg_biomarkers(times, leads, 0.1);
  // Within 1.5 ms: the first and last deflections are below 0.1 % of the
  // peak for about a millisecond at their ends. (A level of 10 % of the
  // peak sees the main wave alone: about 50-80 ms.)
  CHECK(b.qrs_onset == Approx(30).margin(1.5));
  CHECK(b.qrs_end == Approx(110).margin(1.5));
  CHECK(b.qrs_duration == Approx(80).margin(3));
  for (unsigned int l = 0; l < 12; ++l)
    CHECK(b.r_amplitude[l] >= std::max(last[l], 0.0) - 1e-12);
}


TEST_CASE("The lead field of a planar front gives the exact integral and the "
          "far field of a double layer",
          "[ecg][verification]")
{
  const auto   electrodes = slab_electrodes();
  const double sigma_l = 0.3, sigma_t = 0.1, sigma_b = 0.2, delta = 0.5;

  std::ostringstream table;
  table << std::setprecision(4)
        << "mV at the electrodes (relative difference to the exact value)\n";
  const auto check = [&](const std::string &name,
                         const unsigned int cells_per_mm,
                         const unsigned int degree,
                         const bool         tetrahedra,
                         const unsigned int fibre) {
    const auto   phi   = lead_field_potentials(electrodes,
                                           cells_per_mm,
                                           degree,
                                           tetrahedra,
                                           fibre,
                                           sigma_l,
                                           sigma_t,
                                           sigma_b,
                                           delta);
    const double sigma = fibre == 0 ? sigma_l : sigma_t;
    table << name << ":";
    for (unsigned int e = 0; e < electrodes.size(); ++e)
      {
        const double exact =
          exact_potential(electrodes[e], sigma, sigma_b, delta);
        table << " " << phi[e] << " (" << std::showpos
              << (phi[e] - exact) / std::abs(exact) << std::noshowpos << ")";
        CHECK(phi[e] == Approx(exact).epsilon(0.01));
      }
    table << "\n";
    return phi;
  };
  const auto q1 = check("Q1 h = 0.25, fibres along x", 4, 1, false, 0);
  check("Q1 h = 0.25, fibres along y", 4, 1, false, 1);
  check("Q2 h = 0.5, fibres along x", 2, 2, false, 0);
  check("P1 tetrahedra h = 0.5, fibres along x", 2, 1, true, 0);
  INFO(table.str());
  std::cout << table.str();

  // The front moves towards +x: positive ahead of it, negative behind.
  CHECK(q1[0] > 0);
  CHECK(q1[1] < 0);
  // The far field of the uniform double layer of strength σ ΔV on the
  // front plane (the limit delta -> 0): φ = −σ ΔV Ω(x0) / (4π σ_b), ΔV = V
  // behind - V ahead = 100 mV.
  for (const unsigned int e : {3u, 4u})
    {
      const double layer = -sigma_l * 100.0 * solid_angle(x0, electrodes[e]) /
                           (4 * M_PI * sigma_b);
      std::cout << "double layer at electrode " << e << ": " << layer
                << ", relative difference " << (q1[e] - layer) / std::abs(layer)
                << "\n";
      CHECK(q1[e] == Approx(layer).epsilon(0.01));
    }
}


TEST_CASE("The ECG of a monodomain front converges under mesh refinement",
          "[ecg][verification]")
{
  // The tissue of the default heartbeat (parameters/lv_heartbeat.prm:
  // Mitchell-Schaeffer, 0.493 / 0.107 mS/mm, lumped mass) on a 12 x 4 x 2
  // mm slab, fibres along x, stimulated at x <= 1 mm; the nine electrodes
  // around it; 0 ... 24 ms (the front crosses the slab), sampled every
  // 0.5 ms.
  auto params        = Parameters::defaults("Mitchell-Schaeffer");
  params.sigma_l     = 0.493;
  params.sigma_t     = 0.107;
  params.time_step   = 0.05;
  params.stimuli     = parse_stimuli("s: box 0 0 0 1 4 2 from 0 for 2 at 50");
  params.ecg.enabled = true;
  params.ecg.electrodes = parse_electrodes(
    "RA: -80 60 40; LA: 100 60 40; LL: 6 -80 -60; V1: 30 2 1; "
    "V2: 6 20 1; V3: -18 2 1; V4: 6 2 16; V5: 24 16 8; V6: -12 -12 -6");
  std::vector<std::vector<double>> series; // per mesh: all samples, leads
  std::ostringstream               table;
  table << std::setprecision(3) << "cells/mm  DOFs  peak V2 [mV]  L2 to next\n";
  std::vector<unsigned long long> dofs;
  std::vector<double>             peaks;
  for (const unsigned int n : {1u, 2u, 4u})
    {
      test_support::EPBox box;
      box.upper = dealii::Point<3>(12, 4, 2);
      box.cells = {{12 * n, 4 * n, 2 * n}};
      box.fibre = test_support::unit_vector(0);
      std::vector<double> samples;
      double              peak = 0;
      const auto          result =
        test_support::run_ep_box(params,
                                 box,
                                 24.0,
                                 0.5,
                                 {},
                                 MPI_COMM_WORLD,
                                 [&](const Monodomain &ep) {
                                   const auto leads = ep.ecg_leads();
                                   samples.insert(samples.end(),
                                                  leads.begin(),
                                                  leads.end());
                                   peak = std::max(peak, std::abs(leads[7]));
                                 });
      series.push_back(samples);
      dofs.push_back(result.n_dofs);
      peaks.push_back(peak);
    }
  std::vector<double> differences;
  for (unsigned int k = 0; k + 1 < series.size(); ++k)
    {
      double diff = 0, norm = 0;
      for (unsigned int i = 0; i < series[k].size(); ++i)
        {
          diff += std::pow(series[k][i] - series[k + 1][i], 2);
          norm += std::pow(series[k + 1][i], 2);
        }
      differences.push_back(std::sqrt(diff / norm));
    }
  for (unsigned int k = 0; k < series.size(); ++k)
    {
      table << std::setw(8) << (1u << k) << std::setw(7) << dofs[k]
            << std::setw(13) << peaks[k];
      if (k < differences.size())
        table << std::setw(12) << differences[k];
      table << "\n";
    }
  INFO(table.str());
  std::cout << table.str();
  // The two finest meshes within 5 % (relative L2 over time and leads), and
  // the difference shrinking.
  CHECK(differences.back() < 0.05);
  CHECK(differences.back() < differences.front());
}
