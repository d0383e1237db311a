// SPDX-License-Identifier: GPL-3.0-or-later
// The shooter hierarchy's multipole expansion against the exact linear-source
// irradiance (third-order convergence), the batched expansion against the
// point-by-point one, and the recorded transport's regrouping of each
// point's nodes into batches (every pair kept exactly once).
#include "penumbraLinearSource.h"
#include "penumbraRecordedTransport.h"
#include "penumbraShooterHierarchy.h"
#include "penumbraTesting.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

using namespace penumbra;

namespace
{

/// Leaves of a small "shelf": triangles on three faces of a box (normals
/// +z, +x, -y) with random linear radiance, so that nodes mixing normals exist.
ShooterHierarchy Shelf(std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> value(0.2, 2.0);
  ShooterHierarchy tree;
  tree.Origin = Vec3(0.5, 0.5, 0.5);
  const Vec3 normals[3] = { Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, -1, 0) };
  for (int face = 0; face < 3; ++face)
  {
    for (int i = 0; i < 4; ++i)
    {
      for (int j = 0; j < 4; ++j)
      {
        const double u0 = 0.25 * i, v0 = 0.25 * j;
        const auto at = [face](double u, double v) {
          return face == 0 ? Vec3(u, v, 1.0) : (face == 1 ? Vec3(1.0, u, v) : Vec3(u, 0.0, v));
        };
        const Vec3 quad[4] = { at(u0, v0), at(u0 + 0.25, v0), at(u0 + 0.25, v0 + 0.25),
          at(u0, v0 + 0.25) };
        for (int t = 0; t < 2; ++t)
        {
          Vec3 p[3] = { quad[0], quad[1 + t], quad[2 + t] };
          if (Dot(Cross(p[1] - p[0], p[2] - p[0]), normals[face]) < 0.0)
          {
            std::swap(p[1], p[2]);
          }
          const RGB v[3] = { RGB(value(rng), value(rng), value(rng)),
            RGB(value(rng), value(rng), value(rng)), RGB(value(rng), value(rng), value(rng)) };
          Leaf leaf = MakeLeaf(p, v, tree.Origin);
          leaf.Surface = face;
          leaf.Normal = normals[face];
          tree.Leaves.push_back(leaf);
        }
      }
    }
  }
  tree.Build();
  return tree;
}

/// The exact irradiance at x from every leaf under `id`.
RGB ExactBelow(const ShooterHierarchy& tree, int id, const Vec3& x, const Vec3& n)
{
  const Node& node = tree.Nodes[id];
  if (node.Left < 0)
  {
    const Leaf& leaf = tree.Leaves[node.LeafIndex];
    return LinearTriangleIrradiance(x, n, leaf.Points, leaf.Values, leaf.Normal);
  }
  return ExactBelow(tree, node.Left, x, n) + ExactBelow(tree, node.Right, x, n);
}

} // namespace

// A single-normal node seen from ever farther: the expansion's error falls
// as the cube of radius / distance (second-order multipole).
PENUMBRA_TEST(ExpansionConvergesAtThirdOrder)
{
  std::mt19937_64 rng(3);
  ShooterHierarchy tree = Shelf(rng);
  // The deepest one-normal inner node on the +z face.
  int chosen = -1;
  for (int id = 0; id < static_cast<int>(tree.Nodes.size()); ++id)
  {
    const Node& node = tree.Nodes[id];
    if (node.Left >= 0 && node.Mixed < 0 && node.Surface == 0 &&
      (chosen < 0 || node.Radius > tree.Nodes[chosen].Radius))
    {
      chosen = id;
    }
  }
  PENUMBRA_EXPECT(chosen >= 0);
  if (chosen < 0)
  {
    return;
  }
  const Node& node = tree.Nodes[chosen];
  const Vec3 n = Normalized(Vec3(0.2, 0.1, -1.0));
  const Vec3 direction = Normalized(Vec3(0.3, -0.2, 1.0));
  double previous = 0.0;
  for (int step = 0; step < 4; ++step)
  {
    const double distance = node.Radius * 8.0 * std::pow(2.0, step);
    const Vec3 x = node.Centroid + direction * distance;
    const RGB expanded = tree.Irradiance(node, x, n);
    const RGB exact = ExactBelow(tree, chosen, x, n);
    double error = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      error = std::max(error, std::abs(expanded[c] - exact[c]) / exact[c]);
    }
    std::printf("radius/distance %.4f: largest relative error %.3g\n", node.Radius / distance, error);
    PENUMBRA_EXPECT(error < 1e-3 * std::pow(node.Radius / distance * 8.0, 3));
    if (step > 0)
    {
      // Halving radius / distance divides the error by about 8.
      PENUMBRA_EXPECT(error < previous / 6.0);
    }
    previous = error;
  }
}

// AddIrradiance over a batch equals Irradiance point by point, for every
// node (one normal or mixed), any batch size, with and without use flags,
// points behind the node's planes included.
PENUMBRA_TEST(BatchedExpansionMatchesPointByPoint)
{
  std::mt19937_64 rng(5);
  ShooterHierarchy tree = Shelf(rng);
  std::uniform_real_distribution<double> coordinate(-2.0, 3.0);
  std::bernoulli_distribution coin(0.6);
  bool mixedSeen = false;
  double largest = 0.0;
  for (std::size_t count : { 1, 3, 4, 7, 13 })
  {
    std::vector<Vec3> xs(count), ns(count);
    PointBatch batch;
    batch.Reset(count);
    std::vector<unsigned char> use(BatchStride(count), 0);
    for (std::size_t k = 0; k < count; ++k)
    {
      xs[k] = Vec3(coordinate(rng), coordinate(rng), coordinate(rng));
      ns[k] = Normalized(Vec3(coordinate(rng), coordinate(rng), coordinate(rng)));
      batch.X[k] = xs[k].X;
      batch.Y[k] = xs[k].Y;
      batch.Z[k] = xs[k].Z;
      batch.NX[k] = ns[k].X;
      batch.NY[k] = ns[k].Y;
      batch.NZ[k] = ns[k].Z;
      use[k] = coin(rng) ? 1 : 0;
    }
    PointBatch masked = batch;
    std::vector<RGB> all(count), some(count);
    for (const Node& node : tree.Nodes)
    {
      mixedSeen = mixedSeen || node.Mixed >= 0;
      tree.AddIrradiance(node, batch);
      tree.AddIrradiance(node, masked, use.data());
      for (std::size_t k = 0; k < count; ++k)
      {
        const RGB e = tree.Irradiance(node, xs[k], ns[k]);
        all[k] += e;
        some[k] += use[k] ? e : RGB();
      }
    }
    for (std::size_t k = 0; k < count; ++k)
    {
      const RGB got(batch.R[k], batch.G[k], batch.B[k]);
      const RGB gotSome(masked.R[k], masked.G[k], masked.B[k]);
      for (int c = 0; c < 3; ++c)
      {
        largest = std::max(largest, std::abs(got[c] - all[k][c]));
        PENUMBRA_EXPECT_NEAR(got[c], all[k][c], 1e-12 * std::max(1.0, std::abs(all[k][c])));
        PENUMBRA_EXPECT_NEAR(gotSome[c], some[k][c], 1e-12 * std::max(1.0, std::abs(some[k][c])));
      }
    }
  }
  std::printf("largest difference batch - point by point: %.3g\n", largest);
  PENUMBRA_EXPECT(mixedSeen);
}

// Regrouping a unit's per-point nodes keeps every (point, node) pair once:
// in Shared when every point has it, in Partial (flagged) when at least
// half do, else in the point's own list, in its order.
PENUMBRA_TEST(BatchCommonNodesKeepsEveryPair)
{
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> pick(0, 39);
  for (int count : { 1, 2, 5, 9, 16 })
  {
    TransportUnit unit;
    unit.Shared = { 100 };
    std::vector<std::set<int>> before(count);
    std::vector<std::vector<int>> order(count);
    for (int k = 0; k < count; ++k)
    {
      for (int node : { 1, 2 }) // every point's
      {
        before[k].insert(node);
        order[k].push_back(node);
      }
      for (int r = 0; r < 12; ++r)
      {
        const int node = k % 2 == 0 && r < 3 ? 3 + r : 10 + pick(rng);
        if (before[k].insert(node).second)
        {
          order[k].push_back(node);
        }
      }
      unit.Nodes.insert(unit.Nodes.end(), order[k].begin(), order[k].end());
      unit.NodeEnd.push_back(static_cast<int>(unit.Nodes.size()));
    }
    std::vector<int> uses, batch;
    BatchCommonNodes(unit, count, uses, batch);
    PENUMBRA_EXPECT(std::all_of(uses.begin(), uses.end(), [](int u) { return u == 0; }));
    PENUMBRA_EXPECT(std::all_of(batch.begin(), batch.end(), [](int b) { return b == -1; }));
    PENUMBRA_EXPECT(unit.PartialUse.size() == unit.Partial.size() * BatchStride(count));
    for (int k = 0; k < count; ++k)
    {
      std::multiset<int> after(unit.Shared.begin() + 1, unit.Shared.end());
      std::vector<int> own;
      for (int i = k == 0 ? 0 : unit.NodeEnd[k - 1]; i < unit.NodeEnd[k]; ++i)
      {
        after.insert(unit.Nodes[i]);
        own.push_back(unit.Nodes[i]);
      }
      for (std::size_t p = 0; p < unit.Partial.size(); ++p)
      {
        if (unit.PartialUse[p * BatchStride(count) + k])
        {
          after.insert(unit.Partial[p]);
        }
        // The padding is never flagged.
        for (std::size_t pad = count; pad < BatchStride(count); ++pad)
        {
          PENUMBRA_EXPECT(unit.PartialUse[p * BatchStride(count) + pad] == 0);
        }
      }
      PENUMBRA_EXPECT(after == std::multiset<int>(before[k].begin(), before[k].end()));
      // What stays per point keeps its order.
      std::vector<int> expected;
      for (int node : order[k])
      {
        if (std::find(own.begin(), own.end(), node) != own.end())
        {
          expected.push_back(node);
        }
      }
      PENUMBRA_EXPECT(own == expected);
    }
    if (count >= 2)
    {
      // Nodes 1 and 2 are every point's: shared, after the unit's own.
      PENUMBRA_EXPECT(unit.Shared.size() >= 3 && unit.Shared[0] == 100);
    }
  }
}
