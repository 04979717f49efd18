// MatrixFree and its evaluation kernels on the SIMD width of the matrix-free
// mechanics (matrix_free_simd.h), which the installed deal.II, configured
// without vectorization, does not provide. Empty without SYSTOLE_SIMD.
#ifdef SYSTOLE_MATRIX_FREE_SIMD_UNIT

#  include "mechanics/matrix_free_instantiation.h"

using SystoleLanes = dealii::VectorizedArray<double, SYSTOLE_MATRIX_FREE_LANES>;
static_assert(SystoleLanes::size() == SYSTOLE_MATRIX_FREE_LANES,
              "compile this file with the matrix-free SIMD options");

SYSTOLE_INSTANTIATE_MATRIX_FREE(SystoleLanes);

#endif
