# The matrix-free mechanics on the build machine's SIMD width (issue 40). Debian's deal.II is
# configured without vectorization: VectorizedArray<double> has one lane, and MatrixFree batches
# one cell. With SYSTOLE_SIMD on, the units of the matrix-free mechanics are compiled for AVX-512
# (8 doubles) or AVX2 (4), make deal.II's VectorizedArray of that width available
# (src/mechanics/matrix_free_simd.h, force-included) and instantiate MatrixFree on it
# (matrix_free_instantiations.cc), as a deal.II built with -march=native would. `auto` takes the widest the build machine runs; the binary then
# needs that instruction set (Systole is built where it runs; `off` for a portable build).
set(SYSTOLE_SIMD "auto" CACHE STRING
  "SIMD width of the matrix-free mechanics: auto (the build machine's widest), avx512, avx2 or off")
set_property(CACHE SYSTOLE_SIMD PROPERTY STRINGS auto avx512 avx2 off)

include(CheckCXXSourceRuns)
function(systole_cpu_runs feature result)
  set(CMAKE_REQUIRED_QUIET ON)
  check_cxx_source_runs("
    int main() { __builtin_cpu_init(); return __builtin_cpu_supports(\"${feature}\") ? 0 : 1; }"
    ${result})
endfunction()

set(_simd ${SYSTOLE_SIMD})
if(_simd STREQUAL "auto")
  systole_cpu_runs(avx512f SYSTOLE_CPU_AVX512F)
  systole_cpu_runs(avx2 SYSTOLE_CPU_AVX2)
  systole_cpu_runs(fma SYSTOLE_CPU_FMA)
  if(SYSTOLE_CPU_AVX512F)
    set(_simd avx512)
  elseif(SYSTOLE_CPU_AVX2 AND SYSTOLE_CPU_FMA)
    set(_simd avx2)
  else()
    set(_simd off)
  endif()
endif()

if(_simd STREQUAL "avx512")
  set(_lanes 8)
  set(_flags -mavx512f -mavx512dq -mavx512vl -mfma)
elseif(_simd STREQUAL "avx2")
  set(_lanes 4)
  set(_flags -mavx2 -mfma)
elseif(_simd STREQUAL "off")
  set(_lanes 1)
else()
  message(FATAL_ERROR "SYSTOLE_SIMD=${SYSTOLE_SIMD}: expected auto, avx512, avx2 or off.")
endif()
message(STATUS "Matrix-free mechanics: SYSTOLE_SIMD=${SYSTOLE_SIMD} -> ${_simd} (${_lanes} lanes)")

# The units that include src/mechanics/matrix_free_tangent_impl.h (and the benchmark's).
set(SYSTOLE_MATRIX_FREE_LANES ${_lanes})
set(_dir ${CMAKE_CURRENT_SOURCE_DIR}/src/mechanics)
set(_units ${_dir}/matrix_free_tangent.cc ${_dir}/matrix_free_solver.cc
  ${_dir}/matrix_free_mixed_solver.cc ${_dir}/matrix_free_multigrid.cc
  ${_dir}/matrix_free_instantiations.cc)
set_property(SOURCE ${_units} APPEND PROPERTY COMPILE_DEFINITIONS
  SYSTOLE_MATRIX_FREE_LANES=${_lanes})
if(_lanes GREATER 1)
  # (GCC 12 warns of its own AVX-512 intrinsics' undefined vectors.)
  set_source_files_properties(${_units} PROPERTIES
    COMPILE_OPTIONS "-include;${_dir}/matrix_free_simd.h;${_flags};-Wno-maybe-uninitialized;-Wno-uninitialized"
    SKIP_PRECOMPILE_HEADERS ON)
endif()
