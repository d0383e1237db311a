// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraDecimationCollapse.cxx
 * @brief The display decimation's collapses: the candidates of a point, the
 * cost of a collapse (shape, link condition, the error at every removed
 * point it moves), and the collapse itself.
 */
#include "penumbraDecimator.h"

#include <algorithm>
#include <cmath>

namespace penumbra
{
namespace detail
{

//------------------------------------------------------------------------------
bool Decimator::HasShape(const std::array<int, 3>& tri) const
{
  double longest = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const double du = this->U(tri[(k + 1) % 3]) - this->U(tri[k]);
    const double dv = this->V(tri[(k + 1) % 3]) - this->V(tri[k]);
    longest = std::max(longest, du * du + dv * dv);
  }
  return this->Area(tri[0], tri[1], tri[2]) > MinimumShape * longest;
}

//------------------------------------------------------------------------------
bool Decimator::Moved(int t, int u, int v, std::array<int, 3>& tri) const
{
  tri = this->Triangles[static_cast<std::size_t>(t)];
  if (tri[0] == v || tri[1] == v || tri[2] == v)
  {
    return false;
  }
  for (int& w : tri)
  {
    w = w == u ? v : w;
  }
  return true;
}

//------------------------------------------------------------------------------
void Decimator::Barycentric(int p, int a, int b, int c, double w[3]) const
{
  const double area = this->Area(a, b, c);
  w[0] = this->Area(p, b, c) / area;
  w[1] = this->Area(a, p, c) / area;
  w[2] = 1.0 - w[0] - w[1];
}

//------------------------------------------------------------------------------
void Decimator::Neighbours(int x, std::vector<int>& out) const
{
  out.clear();
  for (const int t : this->Stars[static_cast<std::size_t>(x)])
  {
    for (const int w : this->Triangles[static_cast<std::size_t>(t)])
    {
      if (w != x && std::find(out.begin(), out.end(), w) == out.end())
      {
        out.push_back(w);
      }
    }
  }
}

//------------------------------------------------------------------------------
void Decimator::Targets(int u, std::vector<int>& out) const
{
  const std::vector<int>& f = this->Features[static_cast<std::size_t>(u)];
  out.clear();
  if (this->Pinned[static_cast<std::size_t>(u)])
  {
    return;
  }
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    if (!this->HasShape(this->Triangles[static_cast<std::size_t>(t)]))
    {
      return;
    }
  }
  if (f.empty())
  {
    this->Neighbours(u, out);
    return;
  }
  if (f.size() != 2)
  {
    return;
  }
  const double ax = this->U(f[0]) - this->U(u), ay = this->V(f[0]) - this->V(u);
  const double bx = this->U(f[1]) - this->U(u), by = this->V(f[1]) - this->V(u);
  const double cross = ax * by - ay * bx;
  const double dot = ax * bx + ay * by;
  const double scale = std::sqrt((ax * ax + ay * ay) * (bx * bx + by * by));
  if (dot < 0.0 && std::abs(cross) <= 1e-9 * scale)
  {
    out = f;
  }
}

//------------------------------------------------------------------------------
double Decimator::Cost(int u, int v, bool all)
{
  // Link condition (checked for the collapse itself, not for the queue's
  // estimate): the common neighbours of u and v are the vertices opposite
  // their edge, else the collapse would fold the mesh.
  if (all)
  {
    this->HomesOf = { { -1, -1 } };
    std::vector<int>& nu = this->Scratch0;
    std::vector<int>& nv = this->Scratch1;
    this->Neighbours(u, nu);
    this->Neighbours(v, nv);
    int opposite = 0;
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      const std::array<int, 3>& tri = this->Triangles[static_cast<std::size_t>(t)];
      opposite += (tri[0] == v || tri[1] == v || tri[2] == v) ? 1 : 0;
    }
    if (opposite == 0)
    {
      return 2.0;
    }
    int common = 0;
    for (const int w : nu)
    {
      common += std::find(nv.begin(), nv.end(), w) != nv.end() ? 1 : 0;
    }
    if (common != opposite)
    {
      return 2.0;
    }
  }
  // The new triangles keep their orientation and a shape.
  std::size_t held = 1;
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    std::array<int, 3> tri;
    held += this->Removed[static_cast<std::size_t>(t)].size();
    if (this->Moved(t, u, v, tri) && !this->HasShape(tri))
    {
      return 2.0;
    }
  }
  if (held > this->Cap * (this->Stars[static_cast<std::size_t>(u)].size()))
  {
    return 2.0;
  }
  if (!all)
  {
    int home = -1;
    return this->PointCost(u, u, v, -1, home);
  }
  this->Fan.clear();
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    std::array<int, 3> tri;
    if (this->Moved(t, u, v, tri))
    {
      this->Fan.push_back({ t, tri, this->Area(tri[0], tri[1], tri[2]) });
    }
  }
  int home = -1;
  double cost = this->PointCost(u, u, v, -1, home);
  // Where every point lands, for Collapse (the same location it would
  // compute again).
  this->Homes.clear();
  this->Homes.emplace_back(u, home);
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    for (const int p : this->Removed[static_cast<std::size_t>(t)])
    {
      if (cost > 1.0)
      {
        this->Fan.clear();
        return cost;
      }
      cost = std::max(cost, this->PointCost(p, u, v, t, home));
      this->Homes.emplace_back(p, home);
    }
  }
  this->Fan.clear();
  if (cost <= 1.0)
  {
    this->HomesOf = { { u, v } };
  }
  return cost;
}

//------------------------------------------------------------------------------
int Decimator::Locate(int p, int u, int v, double w[3], int hint) const
{
  if (!this->Fan.empty())
  {
    return this->LocateInFan(p, w, hint);
  }
  std::array<int, 3> tri;
  if (hint >= 0 && this->Moved(hint, u, v, tri))
  {
    this->Barycentric(p, tri[0], tri[1], tri[2], w);
    if (std::min(w[0], std::min(w[1], w[2])) >= 0.0)
    {
      return hint;
    }
  }
  int best = -1;
  double bestMargin = -1e300;
  double bestW[3] = { 0.0, 0.0, 0.0 };
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    if (!this->Moved(t, u, v, tri))
    {
      continue;
    }
    double b[3];
    this->Barycentric(p, tri[0], tri[1], tri[2], b);
    const double margin = std::min(b[0], std::min(b[1], b[2]));
    if (margin > bestMargin)
    {
      bestMargin = margin;
      best = t;
      std::copy(b, b + 3, bestW);
    }
  }
  std::copy(bestW, bestW + 3, w);
  return bestMargin >= -LocationSlack ? best : -1;
}

//------------------------------------------------------------------------------
int Decimator::LocateInFan(int p, double w[3], int hint) const
{
  const auto barycentric = [this, p](const FanTriangle& f, double b[3]) {
    b[0] = this->Area(p, f.Corners[1], f.Corners[2]) / f.Area;
    b[1] = this->Area(f.Corners[0], p, f.Corners[2]) / f.Area;
    b[2] = 1.0 - b[0] - b[1];
  };
  if (hint >= 0)
  {
    for (const FanTriangle& f : this->Fan)
    {
      if (f.Triangle == hint)
      {
        barycentric(f, w);
        if (std::min(w[0], std::min(w[1], w[2])) >= 0.0)
        {
          return hint;
        }
        break;
      }
    }
  }
  int best = -1;
  double bestMargin = -1e300;
  double bestW[3] = { 0.0, 0.0, 0.0 };
  for (const FanTriangle& f : this->Fan)
  {
    double b[3];
    barycentric(f, b);
    const double margin = std::min(b[0], std::min(b[1], b[2]));
    if (margin > bestMargin)
    {
      bestMargin = margin;
      best = f.Triangle;
      std::copy(b, b + 3, bestW);
      if (margin > InsideMargin)
      {
        break;
      }
    }
  }
  std::copy(bestW, bestW + 3, w);
  return bestMargin >= -LocationSlack ? best : -1;
}

//------------------------------------------------------------------------------
double Decimator::PointTolerance(int p, int c) const
{
  const std::size_t k = static_cast<std::size_t>(c);
  if (!(this->LocalFraction > 0.0))
  {
    return this->Tolerance[k];
  }
  return std::max(this->Relative[k],
    std::min(this->Absolute[k], this->LocalFraction * std::abs(this->Value(p, c))));
}

//------------------------------------------------------------------------------
double Decimator::PointCost(int p, int u, int v, int hint, int& home) const
{
  double w[3];
  const int t = this->Locate(p, u, v, w, hint);
  home = t;
  if (t < 0)
  {
    return 2.0;
  }
  std::array<int, 3> tri;
  this->Moved(t, u, v, tri); // Locate returns triangles that stay
  double cost = 0.0;
  for (int c = 0; c < this->Channels; ++c)
  {
    const double display = w[0] * this->Value(tri[0], c) + w[1] * this->Value(tri[1], c) +
      w[2] * this->Value(tri[2], c);
    const double error =
      std::abs(display - this->Value(p, c)) / this->PointTolerance(p, c);
    if (!(error <= 1.0))
    {
      return 2.0; // also when not finite
    }
    cost = std::max(cost, error);
  }
  return cost;
}

//------------------------------------------------------------------------------
void Decimator::Push(int u)
{
  std::vector<int> targets;
  this->Targets(u, targets);
  double best = 2.0;
  int to = -1;
  for (const int v : targets)
  {
    const double cost = this->Cost(u, v, false);
    if (cost < best || (cost == best && to >= 0 && v < to))
    {
      best = cost;
      to = v;
    }
  }
  if (to >= 0 && best <= 1.0)
  {
    this->Queue.push({ best, u, to, this->Version[static_cast<std::size_t>(u)] });
    this->Queued[static_cast<std::size_t>(u)] = 1;
  }
}

//------------------------------------------------------------------------------
void Decimator::Collapse(int u, int v)
{
  // The homes were found by the check of this collapse, before the
  // triangles change (Locate reads the old star).
  std::vector<std::pair<int, int>> homes;
  if (this->HomesOf[0] == u && this->HomesOf[1] == v)
  {
    homes.swap(this->Homes);
  }
  else
  {
    double w[3];
    homes.emplace_back(u, this->Locate(u, u, v, w, -1));
    for (const int t : this->Stars[static_cast<std::size_t>(u)])
    {
      for (const int p : this->Removed[static_cast<std::size_t>(t)])
      {
        homes.emplace_back(p, this->Locate(p, u, v, w, t));
      }
    }
  }
  this->HomesOf = { { -1, -1 } };
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    this->Removed[static_cast<std::size_t>(t)].clear();
  }
  for (const int t : this->Stars[static_cast<std::size_t>(u)])
  {
    std::array<int, 3>& tri = this->Triangles[static_cast<std::size_t>(t)];
    if (tri[0] == v || tri[1] == v || tri[2] == v)
    {
      this->Alive[static_cast<std::size_t>(t)] = 0;
      for (const int w : tri)
      {
        if (w != u)
        {
          std::vector<int>& star = this->Stars[static_cast<std::size_t>(w)];
          star.erase(std::remove(star.begin(), star.end(), t), star.end());
        }
      }
      continue;
    }
    for (int& w : tri)
    {
      w = w == u ? v : w;
    }
    this->Stars[static_cast<std::size_t>(v)].push_back(t);
  }
  for (const auto& home : homes)
  {
    // Cost() accepted every point, so every one has a home.
    this->Removed[static_cast<std::size_t>(home.second)].push_back(home.first);
  }
  this->Stars[static_cast<std::size_t>(u)].clear();
  this->Gone[static_cast<std::size_t>(u)] = 1;
  // Along a feature run: v and the run's other neighbour w become neighbours.
  std::vector<int>& fu = this->Features[static_cast<std::size_t>(u)];
  if (fu.size() == 2)
  {
    const int w = fu[0] == v ? fu[1] : fu[0];
    for (int& x : this->Features[static_cast<std::size_t>(v)])
    {
      x = x == u ? w : x;
    }
    for (int& x : this->Features[static_cast<std::size_t>(w)])
    {
      x = x == u ? v : x;
    }
  }
  fu.clear();
  // Everything around v changed.
  std::vector<int> around;
  this->Neighbours(v, around);
  around.push_back(v);
  for (const int x : around)
  {
    ++this->Version[static_cast<std::size_t>(x)];
    if (!this->Queued[static_cast<std::size_t>(x)])
    {
      this->Push(x);
    }
  }
}

} // namespace detail
} // namespace penumbra
