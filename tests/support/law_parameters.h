#pragma once

#include <deal.II/base/tensor.h>

#include "fibres/fibre_basis.h"
#include "materials/holzapfel_ogden.h"
#include "materials/passive_law.h"

#include <memory>
#include <string>
#include <vector>

/// @file
/// The passive laws under test: for every law of the factory table
/// (Materials::passive_laws().names()) the parameter sets the unit tests use.
/// The tests iterate passive_law_cases(), so their list of laws is the
/// factory's: a law added to the table without an entry in
/// law_parameters.cc fails every one of them.

namespace test_support
{
  /// An axis of the fibre frame along which a law is switched on in tension
  /// only, through a blend of @p width in I4 - 1 = a0.C a0 - 1: there the
  /// energy is only C^2, so central differences must not cross [0, width].
  struct TensionSwitch
  {
    /// &Fibres::FibreBasis::f or &Fibres::FibreBasis::s
    dealii::Tensor<1, 3> systole::Fibres::FibreBasis::*axis;
    double width; ///< blend width in I4 - 1 [-] (0: a hard switch)
  };

  /// One parameter set of a passive law under test.
  struct LawCase
  {
    /// The law's name in the factory table, with the variant in
    /// parentheses when a law has several parameter sets.
    std::string                                           label;
    std::shared_ptr<const systole::Materials::PassiveLaw> law;
    /// True for the law's default Parameters() (the factory test builds the
    /// law by name from the declared defaults and compares).
    bool default_parameters = false;
    /// The axes along which the law has a tension switch (empty for a law
    /// that is smooth everywhere).
    std::vector<TensionSwitch> tension_switches;
  };

  /// Every law of the factory table, in the table's order, with its
  /// parameter sets (the default parameters first, then variants such as
  /// the transversely isotropic Holzapfel-Ogden). law->name() is the factory
  /// name of every case. Throws std::logic_error naming the law and this
  /// file if a law of the table has no parameter sets here.
  std::vector<LawCase>
  passive_law_cases();

  /// The factory names that have parameter sets in law_parameters.cc
  /// (whether or not they are in the factory table; for the coverage test).
  std::vector<std::string>
  laws_with_test_parameters();

  /// Holzapfel-Ogden with the parameters and the logistic tension switch
  /// (k = 100) of Arostica et al. 2025.
  systole::Materials::HolzapfelOgden::Parameters
  arostica_holzapfel_ogden();

  /// Holzapfel-Ogden with the default parameters but no sheet and no
  /// fibre-sheet terms (a_s = a_fs = 0): the transversely isotropic law.
  systole::Materials::HolzapfelOgden::Parameters
  transversely_isotropic_holzapfel_ogden();
} // namespace test_support
