#pragma once

// The explicit instantiations of MatrixFree and its evaluation kernels on a
// VectorizedArray the installed deal.II was not compiled for (it is
// configured without vectorization): SYSTOLE_INSTANTIATE_MATRIX_FREE(VA) in
// one unit compiled for VA's instruction set (matrix_free_instantiations.cc
// for the library's width, the benchmark's 8-lane unit). Include it only
// there: it includes deal.II's template definitions.

// Only the degrees up to 2 in the run-time factories (Q2 and its Q1 level).
#define FE_EVAL_FACTORY_DEGREE_MAX 2
#include <deal.II/matrix_free/evaluation_template_factory.templates.h>
// deal.II 9.4's face factory reuses the include guard of the cell factory.
#undef dealii_matrix_free_evaluation_template_factory_templates_h
#include <deal.II/matrix_free/evaluation_template_face_factory.templates.h>
#include <deal.II/matrix_free/evaluation_template_factory_hanging_nodes.templates.h>
#include <deal.II/matrix_free/mapping_info.templates.h>
#include <deal.II/matrix_free/matrix_free.templates.h>
#include <deal.II/matrix_free/shape_info.templates.h>

// (internal_reinit is a member template that reinit() calls.)
#define SYSTOLE_INSTANTIATE_MATRIX_FREE(VA)                                    \
  template class dealii::MatrixFree<3, double, VA>;                            \
  template void dealii::MatrixFree<3, double, VA>::internal_reinit<double, 3>( \
    const std::shared_ptr<dealii::hp::MappingCollection<3>> &,                 \
    const std::vector<const dealii::DoFHandler<3, 3> *> &,                     \
    const std::vector<const dealii::AffineConstraints<double> *> &,            \
    const std::vector<dealii::IndexSet> &,                                     \
    const std::vector<dealii::hp::QCollection<3>> &,                           \
    const dealii::MatrixFree<3, double, VA>::AdditionalData &);                \
  template struct dealii::internal::MatrixFreeFunctions::ShapeInfo<VA>;        \
  template struct dealii::internal::MatrixFreeFunctions::                      \
    MappingInfo<3, double, VA>;                                                \
  template struct dealii::internal::FEEvaluationFactory<3, VA>;                \
  template struct dealii::internal::FEFaceEvaluationFactory<3, VA>;            \
  template struct dealii::internal::                                           \
    FEEvaluationHangingNodesFactory<3, double, VA>
