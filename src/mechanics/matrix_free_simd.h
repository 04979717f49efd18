#pragma once

// Force-included (the compiler's -include, cmake/SystoleSimd.cmake) as the
// first line of the matrix-free mechanics' units when SYSTOLE_SIMD is on.
// Debian's deal.II is configured without vectorization: VectorizedArray has
// one lane, and MatrixFree is compiled for it only. Raising deal.II's width
// after its config.h (which has already fixed the default width through
// numbers.h) makes the wider VectorizedArray<double, N> available while the
// default stays one lane, so deal.II's compiled classes keep their layout
// in every unit; the matrix-free code names its width (internal::Lanes),
// and matrix_free_instantiations.cc instantiates MatrixFree on it. These
// units are compiled for the build machine's instruction set. Never
// include this file by hand.
#include <deal.II/base/config.h>

#if !defined(SYSTOLE_MATRIX_FREE_LANES) || SYSTOLE_MATRIX_FREE_LANES < 2
#  error \
    "matrix_free_simd.h is for the SIMD units only (cmake/SystoleSimd.cmake)."
#endif

#undef DEAL_II_VECTORIZATION_WIDTH_IN_BITS
#define DEAL_II_VECTORIZATION_WIDTH_IN_BITS (64 * SYSTOLE_MATRIX_FREE_LANES)
/// This unit is compiled for SYSTOLE_MATRIX_FREE_LANES lanes.
#define SYSTOLE_MATRIX_FREE_SIMD_UNIT 1
