// MatrixFree and its evaluation kernels on the SIMD width of the matrix-free
// mechanics (matrix_free_simd.h), which the installed deal.II, configured
// without vectorization, does not provide. Empty without SYSTOLE_SIMD.
#ifdef SYSTOLE_MATRIX_FREE_SIMD_UNIT

// Only the degrees up to 2 in the run-time factories (Q2 and its Q1 level).
#  define FE_EVAL_FACTORY_DEGREE_MAX 2
#  include <deal.II/matrix_free/evaluation_template_factory.templates.h>
// deal.II 9.4's face factory reuses the include guard of the cell factory.
#  undef dealii_matrix_free_evaluation_template_factory_templates_h
#  include <deal.II/matrix_free/evaluation_template_face_factory.templates.h>
#  include <deal.II/matrix_free/evaluation_template_factory_hanging_nodes.templates.h>
#  include <deal.II/matrix_free/mapping_info.templates.h>
#  include <deal.II/matrix_free/matrix_free.templates.h>
#  include <deal.II/matrix_free/shape_info.templates.h>

using SystoleLanes = dealii::VectorizedArray<double, SYSTOLE_MATRIX_FREE_LANES>;
static_assert(SystoleLanes::size() == SYSTOLE_MATRIX_FREE_LANES,
              "compile this file with the matrix-free SIMD options");

template class dealii::MatrixFree<3, double, SystoleLanes>;
// (A member template: reinit() calls it.)
template void
dealii::MatrixFree<3, double, SystoleLanes>::internal_reinit<double, 3>(
  const std::shared_ptr<dealii::hp::MappingCollection<3>> &,
  const std::vector<const dealii::DoFHandler<3, 3> *> &,
  const std::vector<const dealii::AffineConstraints<double> *> &,
  const std::vector<dealii::IndexSet> &,
  const std::vector<dealii::hp::QCollection<3>> &,
  const AdditionalData &);
template struct dealii::internal::MatrixFreeFunctions::ShapeInfo<SystoleLanes>;
template struct dealii::internal::MatrixFreeFunctions::
  MappingInfo<3, double, SystoleLanes>;
template struct dealii::internal::FEEvaluationFactory<3, SystoleLanes>;
template struct dealii::internal::FEFaceEvaluationFactory<3, SystoleLanes>;
template struct dealii::internal::
  FEEvaluationHangingNodesFactory<3, double, SystoleLanes>;

#endif
