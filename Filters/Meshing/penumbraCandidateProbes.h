// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraCandidateProbes.h
 * @brief Candidate points of the adaptive sampler: the key that identifies
 * a candidate across passes (a triangle's centroid or an edge midpoint, on
 * one side of an order-0 line) and its cached evaluation. Private to
 * Penumbra::Meshing.
 *
 * The probing and residual tests are ReceiverSampler members
 * (penumbraCandidateProbes.cxx).
 * Design notes: Documentation/design/sampling.md
 */
#ifndef penumbraCandidateProbes_h
#define penumbraCandidateProbes_h

#include "penumbraVector.h"

#include <cstddef>

namespace penumbra
{
namespace detail
{

/// Key of a candidate point: a triangle's centroid (its three vertex ids,
/// sorted) or an edge midpoint (vertex ids sorted, C = -1 unsided, -2 on the
/// left of A->B, -3 on its right).
struct CandidateKey
{
  int A, B, C;
  bool operator==(const CandidateKey& o) const;
};

/// Hash of a CandidateKey.
struct CandidateKeyHash
{
  std::size_t operator()(const CandidateKey& k) const;
};

/// A candidate's evaluation, kept while its element exists.
struct CandidateValue
{
  RGB Value;
  double Du = 0.0, Dv = 0.0; // side direction of a sided midpoint
  bool Sided = false;
  bool Evaluated = false;
  bool Used = false;
};

} // namespace detail
} // namespace penumbra

#endif
