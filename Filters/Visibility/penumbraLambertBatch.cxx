// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraLambertBatch.h"

#include "penumbraFormFactor.h"
#include "penumbraMath.h"

#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace penumbra
{
namespace detail
{
namespace
{

// Cephes' atan (reduction to |t| <= 0.66, rational approximation), within
// an ulp of glibc's atan and several times cheaper; every operation below
// has its twin in EdgeTerms2, so both give the same bits.
constexpr double Tan3PiOver8 = 2.41421356237309504880;
constexpr double MoreBits = 6.123233995736765886130e-17; // pi/2 - double(pi/2)
constexpr double AtanP0 = 8.750608600031904122785e-1, AtanP1 = 1.615753718733365076637e1,
                 AtanP2 = 7.500855792314704667340e1, AtanP3 = 1.228866684490136173410e2,
                 AtanP4 = 6.485021904942025371773e1;
constexpr double AtanQ0 = 2.485846490142306297962e1, AtanQ1 = 1.650270098316988542046e2,
                 AtanQ2 = 4.328810604912902668951e2, AtanQ3 = 4.853903996359136964868e2,
                 AtanQ4 = 1.945506571482613964425e2;

// The angle of LambertEdgeAngle, atan2(s, c) for s > 0.
inline double EdgeAngle(double s, double c)
{
  const double ac = std::abs(c);
  const bool big = s > Tan3PiOver8 * ac;
  const bool mid = s > 0.66 * ac;
  // atan(s / ac) = base + atan(num / den), |num / den| <= 0.66.
  const double num = big ? -ac : (mid ? s - ac : s);
  const double den = big ? s : (mid ? s + ac : ac);
  const double base = big ? 0.5 * Pi : (mid ? 0.25 * Pi : 0.0);
  const double more = big ? MoreBits : (mid ? 0.5 * MoreBits : 0.0);
  const double t = num / den;
  const double z = t * t;
  const double p = (((-AtanP0 * z - AtanP1) * z - AtanP2) * z - AtanP3) * z - AtanP4;
  const double r = ((((z + AtanQ0) * z + AtanQ1) * z + AtanQ2) * z + AtanQ3) * z + AtanQ4;
  const double a = base + (t * (z * p / r) + more + t);
  return c >= 0.0 ? a : Pi - a;
}

// LambertEdgeTerm of the edge r0 = (u0, v0, h) -> r1 = (u1, v1, h) when
// |r1 x r0|^2 > 1e-280; otherwise returns false and leaves `term`.
inline bool EdgeTerm(
  double u0, double v0, double u1, double v1, double h, const Vec3& n, double& term)
{
  const double cx = v1 * h - h * v0;
  const double cy = h * u0 - u1 * h;
  const double cz = u1 * v0 - v1 * u0;
  const double s2 = cx * cx + cy * cy + cz * cz;
  if (!(s2 > 1e-280))
  {
    return false;
  }
  const double s = std::sqrt(s2);
  const double d = u0 * u1 + v0 * v1 + h * h;
  term = EdgeAngle(s, d) * ((n.X * cx + n.Y * cy + n.Z * cz) / s);
  return true;
}

#if defined(__SSE2__)
inline __m128d Select(__m128d mask, __m128d a, __m128d b)
{
  return _mm_or_pd(_mm_and_pd(mask, a), _mm_andnot_pd(mask, b));
}

// EdgeTerm for the edges e and e + 1, operation for operation. Returns the
// mask of the edges whose term was written.
inline int EdgeTerms2(const double* u0, const double* v0, const double* u1, const double* v1,
  double h, const Vec3& n, double* term)
{
  const __m128d a0 = _mm_loadu_pd(u0), b0 = _mm_loadu_pd(v0);
  const __m128d a1 = _mm_loadu_pd(u1), b1 = _mm_loadu_pd(v1);
  const __m128d hh = _mm_set1_pd(h);
  const __m128d cx = _mm_sub_pd(_mm_mul_pd(b1, hh), _mm_mul_pd(hh, b0));
  const __m128d cy = _mm_sub_pd(_mm_mul_pd(hh, a0), _mm_mul_pd(a1, hh));
  const __m128d cz = _mm_sub_pd(_mm_mul_pd(a1, b0), _mm_mul_pd(b1, a0));
  const __m128d s2 = _mm_add_pd(
    _mm_add_pd(_mm_mul_pd(cx, cx), _mm_mul_pd(cy, cy)), _mm_mul_pd(cz, cz));
  const __m128d ok = _mm_cmpgt_pd(s2, _mm_set1_pd(1e-280));
  const __m128d one = _mm_set1_pd(1.0);
  const __m128d s = _mm_sqrt_pd(Select(ok, s2, one));
  const __m128d c =
    _mm_add_pd(_mm_add_pd(_mm_mul_pd(a0, a1), _mm_mul_pd(b0, b1)), _mm_mul_pd(hh, hh));
  // EdgeAngle(s, c).
  const __m128d sign = _mm_set1_pd(-0.0);
  const __m128d zero = _mm_setzero_pd();
  const __m128d ac = _mm_andnot_pd(sign, c);
  const __m128d big = _mm_cmpgt_pd(s, _mm_mul_pd(_mm_set1_pd(Tan3PiOver8), ac));
  const __m128d mid = _mm_cmpgt_pd(s, _mm_mul_pd(_mm_set1_pd(0.66), ac));
  const __m128d num =
    Select(big, _mm_xor_pd(ac, sign), Select(mid, _mm_sub_pd(s, ac), s));
  const __m128d den = Select(big, s, Select(mid, _mm_add_pd(s, ac), ac));
  const __m128d base =
    Select(big, _mm_set1_pd(0.5 * Pi), Select(mid, _mm_set1_pd(0.25 * Pi), zero));
  const __m128d more =
    Select(big, _mm_set1_pd(MoreBits), Select(mid, _mm_set1_pd(0.5 * MoreBits), zero));
  const __m128d t = _mm_div_pd(num, den);
  const __m128d z = _mm_mul_pd(t, t);
  __m128d p = _mm_sub_pd(_mm_mul_pd(_mm_set1_pd(-AtanP0), z), _mm_set1_pd(AtanP1));
  p = _mm_sub_pd(_mm_mul_pd(p, z), _mm_set1_pd(AtanP2));
  p = _mm_sub_pd(_mm_mul_pd(p, z), _mm_set1_pd(AtanP3));
  p = _mm_sub_pd(_mm_mul_pd(p, z), _mm_set1_pd(AtanP4));
  __m128d r = _mm_add_pd(z, _mm_set1_pd(AtanQ0));
  r = _mm_add_pd(_mm_mul_pd(r, z), _mm_set1_pd(AtanQ1));
  r = _mm_add_pd(_mm_mul_pd(r, z), _mm_set1_pd(AtanQ2));
  r = _mm_add_pd(_mm_mul_pd(r, z), _mm_set1_pd(AtanQ3));
  r = _mm_add_pd(_mm_mul_pd(r, z), _mm_set1_pd(AtanQ4));
  const __m128d q = _mm_div_pd(_mm_mul_pd(z, p), r);
  const __m128d a =
    _mm_add_pd(base, _mm_add_pd(_mm_add_pd(_mm_mul_pd(t, q), more), t));
  const __m128d angle = Select(_mm_cmpge_pd(c, zero), a, _mm_sub_pd(_mm_set1_pd(Pi), a));
  const __m128d dot = _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_set1_pd(n.X), cx),
                                   _mm_mul_pd(_mm_set1_pd(n.Y), cy)),
    _mm_mul_pd(_mm_set1_pd(n.Z), cz));
  _mm_storeu_pd(term, Select(ok, _mm_mul_pd(angle, _mm_div_pd(dot, s)), zero));
  return _mm_movemask_pd(ok);
}
#endif

} // namespace

//------------------------------------------------------------------------------
void LambertBatch::Flush()
{
  const int n = this->Count;
  double* term = this->Term;
  int e = 0;
#if defined(__SSE2__)
  for (; e + 1 < n; e += 2)
  {
    if (EdgeTerms2(this->U0 + e, this->V0 + e, this->U1 + e, this->V1 + e, this->H, this->N,
          term + e) != 3)
    {
      this->Scalar(e);
      this->Scalar(e + 1);
    }
  }
#endif
  for (; e < n; ++e)
  {
    this->Scalar(e);
  }
  for (e = 0; e < n; ++e)
  {
    this->Total += term[e];
  }
  this->Count = 0;
}

//------------------------------------------------------------------------------
void LambertBatch::Scalar(int e)
{
  if (!EdgeTerm(this->U0[e], this->V0[e], this->U1[e], this->V1[e], this->H, this->N, this->Term[e]))
  {
    // Rescaled or vanishing: the general routine.
    this->Term[e] = LambertEdgeTerm(
      Vec3(this->U0[e], this->V0[e], this->H), Vec3(this->U1[e], this->V1[e], this->H), this->N);
  }
}

} // namespace detail
} // namespace penumbra
