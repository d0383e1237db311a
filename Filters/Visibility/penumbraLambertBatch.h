// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraLambertBatch.h
 * Lambert's polygon sum over many edges, computed in blocks: the exact
 * evaluator's inner loop. Each edge term equals LambertEdgeTerm's (an inline
 * arctangent within an ulp of the C library's, two edges at a time where the
 * processor allows, with a scalar twin giving the same bits) and the terms
 * are added in the order the edges came.
 */
#ifndef penumbraLambertBatch_h
#define penumbraLambertBatch_h

#include "penumbraVector.h"

namespace penumbra
{
namespace detail
{

/// Lambert's sum (without 1/(2 pi)) over edges r0 -> r1 with r = (u, v, h):
/// points relative to the query point in a frame where the polygon lies at
/// height h; n is the receiver's normal in that frame.
class LambertBatch
{
public:
  LambertBatch(double h, const Vec3& n)
    : H(h)
    , N(n)
  {
  }

  void Add(double u0, double v0, double u1, double v1)
  {
    if (this->Count == Block)
    {
      this->Flush();
    }
    this->U0[this->Count] = u0;
    this->V0[this->Count] = v0;
    this->U1[this->Count] = u1;
    this->V1[this->Count] = v1;
    ++this->Count;
  }

  /// The sum of the terms so far.
  double Sum()
  {
    this->Flush();
    return this->Total;
  }

private:
  static constexpr int Block = 64;

  void Flush();
  void Scalar(int e);

  double U0[Block], V0[Block], U1[Block], V1[Block], Term[Block];
  int Count = 0;
  double H;
  Vec3 N;
  double Total = 0.0;
};

} // namespace detail
} // namespace penumbra

#endif
