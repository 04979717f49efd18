#pragma once

#include <cstdint>
#include <cstring>
#include <utility>

/// @file
/// exp and log that a compiler vectorizes: branch-free, inline, plain double
/// and 64-bit integer arithmetic, so that a loop over them under `#pragma
/// omp simd` becomes SIMD code at whatever vector width the function is
/// compiled for (glibc's std::exp and std::log are calls the compiler
/// cannot vectorize without -ffast-math). The batched ionic kernels use
/// them (ten_tusscher_panfilov.cc).
///
/// Accuracy: exp within 1 ulp of the correctly rounded value for normal
/// results (Cody-Waite reduction to |r| <= ln 2 / 2 and its Taylor
/// polynomial of degree 13, truncation below 5e-18), log within 1 ulp
/// (fdlibm's __ieee754_log, without branches); both measured against
/// glibc on random arguments in
/// tests/unit/electrophysiology/ionic_batch_test.cc. Special values: exp
/// gives +inf above 709.78, 0 below -745.2 (subnormal results in between)
/// and NaN for NaN; log gives -inf at 0, NaN below 0 or for NaN, +inf at
/// +inf, and handles subnormal arguments.
///
/// The scalar and the vector code of a function perform the same
/// operations in the same order, so they round alike: a node's value does
/// not depend on where it falls in a batch (as long as the compiler
/// contracts multiply-adds alike in both, which it does for one target).

namespace systole::Electrophysiology::SimdMath
{
#define SYSTOLE_SIMD_INLINE inline __attribute__((always_inline))

  SYSTOLE_SIMD_INLINE double
  from_bits(const std::uint64_t u)
  {
    double d;
    std::memcpy(&d, &u, sizeof(d));
    return d;
  }

  SYSTOLE_SIMD_INLINE std::uint64_t
                      to_bits(const double d)
  {
    std::uint64_t u;
    std::memcpy(&u, &d, sizeof(u));
    return u;
  }

  /// 1.5 2^52: x + shifter - shifter rounds |x| < 2^51 to the nearest
  /// integer, and the low bits of x + shifter hold it in two's complement.
  constexpr double shifter = 6755399441055744.0;

  /// 2^k for an integer-valued @p k in [-1022, 1023].
  SYSTOLE_SIMD_INLINE double
  pow2(const double k)
  {
    const std::uint64_t integer = to_bits(k + shifter) - to_bits(shifter);
    return from_bits((integer + 1023) << 52);
  }

  /// n! in double (exact for n <= 18, below 2^53).
  constexpr double
  factorial(const int n)
  {
    return n <= 1 ? 1.0 : n * factorial(n - 1);
  }

  /// 1/n!, rounded once (as the literal 1.0 / n! would be).
  template <int n>
  constexpr double inverse_factorial = 1.0 / factorial(n);

  /// Horner's scheme for sum_{n=first}^{last} x^(n - first)/n!: p = 1/last!,
  /// then p = p x + 1/n! for n = last - 1 - k, k = 0, 1, ... (down to
  /// first).
  template <int first, int last, int... k>
  SYSTOLE_SIMD_INLINE double
  taylor_of_exp(const double x, std::integer_sequence<int, k...>)
  {
    double p = inverse_factorial<last>;
    ((p = p * x + inverse_factorial<last - 1 - k>), ...);
    return p;
  }

  /// sum_{n=first}^{last} x^(n - first)/n! (the partial sums of the Taylor
  /// series of e^x), by Horner's scheme.
  template <int first, int last>
  SYSTOLE_SIMD_INLINE double
  taylor_of_exp(const double x)
  {
    return taylor_of_exp<first, last>(
      x,
      std::make_integer_sequence<int, last - first>());
  }

  /// e^x.
  SYSTOLE_SIMD_INLINE double
  exp(const double x)
  {
    constexpr double log2e = 1.44269504088896338700e+00;
    // ln 2 = ln2_hi + ln2_lo with ln2_hi's last 32 bits zero (fdlibm):
    // k ln2_hi is exact for |k| < 2^20.
    constexpr double ln2_hi = 6.93147180369123816490e-01;
    constexpr double ln2_lo = 1.90821492927058770002e-10;
    // Clamped so that k fits; NaN passes (a comparison with NaN is false).
    const double xc = x > 710.0 ? 710.0 : (x < -746.0 ? -746.0 : x);
    const double k  = (xc * log2e + shifter) - shifter;
    const double r  = (xc - k * ln2_hi) - k * ln2_lo;
    // e^r = sum r^n/n!, n <= 13: |r| <= 0.3466, the rest < 5e-18.
    const double p = taylor_of_exp<0, 13>(r);
    // 2^k in two factors (k in [-1077, 1025]), each a normal number: the
    // product overflows to inf or underflows gradually as it should.
    const double k1 = (0.5 * k + shifter) - shifter;
    return p * pow2(k1) * pow2(k - k1);
  }

  /// ln x.
  SYSTOLE_SIMD_INLINE double
  log(const double x)
  {
    constexpr double ln2_hi = 6.93147180369123816490e-01;
    constexpr double ln2_lo = 1.90821492927058770002e-10;
    constexpr double Lg1    = 6.666666666666735130e-01;
    constexpr double Lg2    = 3.999999999940941908e-01;
    constexpr double Lg3    = 2.857142874366239149e-01;
    constexpr double Lg4    = 2.222219843214978396e-01;
    constexpr double Lg5    = 1.818357216161805012e-01;
    constexpr double Lg6    = 1.531383769920937332e-01;
    constexpr double Lg7    = 1.479819860511658591e-01;
    constexpr double two52  = 4503599627370496.0;
    constexpr double sqrt2  = 1.41421356237309504880;
    // Subnormal x: scaled by 2^54 first.
    const bool          tiny = x < 2.2250738585072014e-308;
    const double        xs   = tiny ? x * 18014398509481984.0 : x;
    const std::uint64_t u    = to_bits(xs);
    // x = 2^e m with m in [1, 2), then in [sqrt(2)/2, sqrt(2)).
    double e = from_bits((u >> 52) | to_bits(two52)) - two52 - 1023.0 -
               (tiny ? 54.0 : 0.0);
    double m = from_bits((u & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL);
    const bool high = m > sqrt2;
    m               = high ? 0.5 * m : m;
    e               = high ? e + 1.0 : e;
    // fdlibm: log(1 + f) = f - hfsq + s (hfsq + R), s = f/(2 + f).
    const double f    = m - 1.0;
    const double s    = f / (2.0 + f);
    const double z    = s * s;
    const double w    = z * z;
    const double t1   = w * (Lg2 + w * (Lg4 + w * Lg6));
    const double t2   = z * (Lg1 + w * (Lg3 + w * (Lg5 + w * Lg7)));
    const double R    = t2 + t1;
    const double hfsq = 0.5 * f * f;
    const double result =
      e * ln2_hi - ((hfsq - (s * (hfsq + R) + e * ln2_lo)) - f);
    // 0 -> -inf, < 0 or NaN -> NaN, +inf -> +inf.
    constexpr double inf = __builtin_inf();
    return x > 0.0 ? (x < inf ? result : inf)
                   : (x == 0.0 ? -inf : __builtin_nan(""));
  }

  /// x/(e^x - 1), continued by 1 at x = 0 (its removable singularity), with
  /// @p exp_x = e^x given: for |x| < 0.5 e^x - 1 from its Taylor series
  /// (no cancellation), elsewhere exp_x - 1.
  SYSTOLE_SIMD_INLINE double
  x_over_expm1(const double x, const double exp_x)
  {
    // (e^x - 1)/x = sum_{n=1}^{18} x^(n-1)/n!: at |x| = 0.5 the rest is
    // below 1e-21.
    const double p = taylor_of_exp<1, 18>(x);
    // |x| < 0.5: x/(x p) = 1/p; elsewhere x/(e^x - 1).
    const bool   small = x < 0.5 && x > -0.5;
    const double num   = small ? 1.0 : x;
    const double den   = small ? p : exp_x - 1.0;
    return num / den;
  }

#undef SYSTOLE_SIMD_INLINE
} // namespace systole::Electrophysiology::SimdMath
