// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraFeatureSize.cxx
 * @brief Lengths of the discontinuity lines through each vertex: collinear
 * segments joined into chains by a union-find.
 */
#include "penumbraFeatureSize.h"

#include "penumbraMath.h"
#include "penumbraSamplingReceiver.h"
#include "penumbraUnionFind.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

//------------------------------------------------------------------------------
// The longest line, not the shortest: a short piece of a line cut off by
// another's visibility ends on that line, which belongs to a large feature.
std::vector<double> DiscontinuityLineLengths(const Receiver& rec)
{
  const auto& segments = rec.Snap.Segments;
  const int ns = static_cast<int>(segments.size());
  const int nv = static_cast<int>(rec.Snap.Vertices.size());
  UnionFind lines(ns);
  std::vector<std::vector<int>> incident(nv);
  std::vector<double> length(ns, 0.0);
  for (int i = 0; i < ns; ++i)
  {
    const auto& seg = segments[i];
    if (seg.Order < 0)
    {
      continue;
    }
    const P2 a = rec.Vertex(seg.VertexA), b = rec.Vertex(seg.VertexB);
    length[i] = std::hypot(b[0] - a[0], b[1] - a[1]);
    incident[seg.VertexA].push_back(i);
    incident[seg.VertexB].push_back(i);
  }
  // Join segments meeting at a vertex in a straight line (opposite directions).
  for (int v = 0; v < nv; ++v)
  {
    const auto& list = incident[v];
    const P2 o = rec.Vertex(v);
    for (std::size_t x = 0; x < list.size(); ++x)
    {
      for (std::size_t y = x + 1; y < list.size(); ++y)
      {
        const auto& s1 = segments[list[x]];
        const auto& s2 = segments[list[y]];
        const P2 p = rec.Vertex(s1.VertexA == v ? s1.VertexB : s1.VertexA);
        const P2 q = rec.Vertex(s2.VertexA == v ? s2.VertexB : s2.VertexA);
        const double ux = p[0] - o[0], uy = p[1] - o[1], wx = q[0] - o[0], wy = q[1] - o[1];
        const double scale = length[list[x]] * length[list[y]];
        if (ux * wx + uy * wy < 0.0 && std::abs(Cross2(ux, uy, wx, wy)) <= 1e-9 * scale)
        {
          lines.Union(list[x], list[y]);
        }
      }
    }
  }
  std::vector<double> chain(ns, 0.0);
  for (int i = 0; i < ns; ++i)
  {
    chain[lines.Find(i)] += length[i];
  }
  std::vector<double> out(nv, HUGE_VAL);
  for (int v = 0; v < nv; ++v)
  {
    if (!incident[v].empty())
    {
      out[v] = 0.0;
    }
    for (int i : incident[v])
    {
      out[v] = std::max(out[v], chain[lines.Find(i)]);
    }
  }
  return out;
}

} // namespace detail
} // namespace penumbra
