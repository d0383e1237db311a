// SPDX-License-Identifier: GPL-3.0-or-later
// The only CGAL translation unit of the discontinuity mesher: one receiver's
// constrained Delaunay triangulation (see penumbraReceiverTriangulation.h).
#include "penumbraReceiverTriangulation.h"

#include "penumbraCGAL.h"

#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <utility>

namespace penumbra
{
namespace detail
{

namespace
{

inline int Ccw(int i)
{
  return (i + 1) % 3;
}
inline int Cw(int i)
{
  return (i + 2) % 3;
}

/// Label of a constrained edge: merged from every input constraint through it.
struct EdgeLabel
{
  int Order = 3;
  int SourceId = -1;
  bool Outline = false;
  bool Removal = false;
};

double TriangleArea3(const Vec3& a, const Vec3& b, const Vec3& c)
{
  return 0.5 * Length(Cross(b - a, c - a));
}

/**
 * One receiver triangulation over a CDT+ type: constraint insertion, edge
 * labels, face classification and extraction. Instantiated for the exact
 * arrangement and for the (double) refinement.
 */
template <class CDTP>
struct Stage
{
  using Face = typename CDTP::Face_handle;
  using VertexHandle = typename CDTP::Vertex_handle;
  using Point = typename CDTP::Point;

  CDTP Cdt;
  std::map<typename CDTP::Constraint_id, int> ConstraintOf;
  const std::vector<Constraint2D>* Constraints = nullptr;
  std::vector<EdgeLabel> Labels;

  // Insert every constraint; the vertices of known 2D points remember them.
  void Insert(const std::vector<Constraint2D>& constraints,
    const std::map<std::pair<double, double>, int>& known, std::size_t& failures)
  {
    this->Constraints = &constraints;
    // End points first, in spatial (Hilbert) order with the previous vertex
    // as hint: point location then walks a short way instead of across the
    // whole triangulation.
    std::vector<std::pair<double, double>> coords;
    coords.reserve(2 * constraints.size());
    for (const Constraint2D& c : constraints)
    {
      coords.emplace_back(c.A[0], c.A[1]);
      coords.emplace_back(c.B[0], c.B[1]);
    }
    std::sort(coords.begin(), coords.end());
    coords.erase(std::unique(coords.begin(), coords.end()), coords.end());
    std::vector<Point> points;
    points.reserve(coords.size());
    for (const auto& c : coords)
    {
      points.emplace_back(c.first, c.second);
    }
    CGAL::spatial_sort(points.begin(), points.end(), typename CDTP::Geom_traits());
    std::map<std::pair<double, double>, VertexHandle> vertexAt;
    VertexHandle hint;
    for (const Point& p : points)
    {
      const double x = CGAL::to_double(p.x()), y = CGAL::to_double(p.y());
      hint = hint == VertexHandle() ? this->Cdt.insert(p) : this->Cdt.insert(p, hint->face());
      vertexAt[std::make_pair(x, y)] = hint;
      auto found = known.find(std::make_pair(x, y));
      if (found != known.end())
      {
        hint->info().Known = found->second;
      }
    }
    for (std::size_t k = 0; k < constraints.size(); ++k)
    {
      const Constraint2D& c = constraints[k];
      try
      {
        VertexHandle va = vertexAt.at(std::make_pair(c.A[0], c.A[1]));
        VertexHandle vb = vertexAt.at(std::make_pair(c.B[0], c.B[1]));
        if (va == vb)
        {
          continue;
        }
        this->ConstraintOf.emplace(this->Cdt.insert_constraint(va, vb), static_cast<int>(k));
      }
      catch (const std::exception&)
      {
        ++failures;
      }
    }
  }

  // Store, in both faces of every constrained edge, the index of its label:
  // the lowest order of the input constraints through the edge (outline -1
  // first), its source, and whether any is an outline or footprint edge.
  void Label()
  {
    this->Labels.clear();
    for (Face f : this->Cdt.all_face_handles())
    {
      for (int i = 0; i < 3; ++i)
      {
        f->info().Label[i] = -1;
      }
    }
    for (auto e = this->Cdt.finite_edges_begin(); e != this->Cdt.finite_edges_end(); ++e)
    {
      Face f = e->first;
      const int i = e->second;
      if (!f->is_constrained(i))
      {
        continue;
      }
      const VertexHandle va = f->vertex(Ccw(i)), vb = f->vertex(Cw(i));
      EdgeLabel label;
      for (auto ctx : this->Cdt.contexts(va, vb))
      {
        auto found = this->ConstraintOf.find(ctx.id());
        if (found == this->ConstraintOf.end())
        {
          continue;
        }
        const Constraint2D& c = (*this->Constraints)[found->second];
        label.Outline = label.Outline || c.Outline;
        label.Removal = label.Removal || c.Removal;
        if (c.Order < label.Order || (c.Order == label.Order && c.SourceId < label.SourceId))
        {
          label.Order = c.Order;
          label.SourceId = c.SourceId;
        }
      }
      if (label.Outline)
      {
        label.Order = -1;
        label.SourceId = -1;
      }
      const int index = static_cast<int>(this->Labels.size());
      this->Labels.push_back(label);
      f->info().Label[i] = index;
      Face g = f->neighbor(i);
      g->info().Label[g->index(f)] = index;
    }
  }

  // Flood fill from the infinite faces: crossing an outline edge toggles bit
  // 0 ("inside the receiver"), crossing a footprint edge toggles bit 1
  // ("under a solid"). Interior discontinuity constraints toggle nothing,
  // which is why the usual nesting-level count of constrained edges is not
  // used as is.
  void Classify()
  {
    for (Face f : this->Cdt.all_face_handles())
    {
      f->info().State = -1;
      f->info().Kept = false;
    }
    std::queue<Face> queue;
    Face start = this->Cdt.infinite_face();
    start->info().State = 0;
    queue.push(start);
    while (!queue.empty())
    {
      Face f = queue.front();
      queue.pop();
      for (int i = 0; i < 3; ++i)
      {
        Face g = f->neighbor(i);
        if (g->info().State >= 0)
        {
          continue;
        }
        int state = f->info().State;
        const int label = f->info().Label[i];
        if (label >= 0)
        {
          state ^= (this->Labels[label].Outline ? 1 : 0) | (this->Labels[label].Removal ? 2 : 0);
        }
        g->info().State = state;
        queue.push(g);
      }
    }
    for (Face f : this->Cdt.finite_face_handles())
    {
      f->info().Kept = f->info().State == 1;
    }
  }

  // The constrained edges with their labels, rounded to double (the input of
  // the refinement stage).
  std::vector<Constraint2D> Arrangement() const
  {
    std::vector<Constraint2D> out;
    for (auto e = this->Cdt.finite_edges_begin(); e != this->Cdt.finite_edges_end(); ++e)
    {
      Face f = e->first;
      const int label = f->info().Label[e->second];
      if (label < 0)
      {
        continue;
      }
      const EdgeLabel& l = this->Labels[label];
      Constraint2D c;
      const Point& a = f->vertex(Ccw(e->second))->point();
      const Point& b = f->vertex(Cw(e->second))->point();
      c.A[0] = CGAL::to_double(a.x());
      c.A[1] = CGAL::to_double(a.y());
      c.B[0] = CGAL::to_double(b.x());
      c.B[1] = CGAL::to_double(b.y());
      if (c.A[0] == c.B[0] && c.A[1] == c.B[1])
      {
        continue;
      }
      c.Order = l.Order;
      c.SourceId = l.SourceId;
      c.Outline = l.Outline;
      c.Removal = l.Removal;
      out.push_back(c);
    }
    return out;
  }

  // Triangles, points (duplicated across order-0 edges) and labelled
  // constrained edges of the kept faces.
  void Extract(const TriangulationInput& input, TriangulationOutput& out)
  {
    CDTP& cdt = this->Cdt;
    std::map<VertexHandle, int> vertexIndex;
    std::vector<Vec3> vertex3;
    auto vertexOf = [&](VertexHandle v) {
      auto found = vertexIndex.find(v);
      if (found != vertexIndex.end())
      {
        return found->second;
      }
      Vec3 p;
      if (v->info().Known >= 0)
      {
        p = input.Known3D[v->info().Known];
      }
      else
      {
        const double x = CGAL::to_double(v->point().x());
        const double y = CGAL::to_double(v->point().y());
        p = input.Origin + x * input.AxisU + y * input.AxisV;
      }
      const int index = static_cast<int>(vertex3.size());
      vertex3.push_back(p);
      vertexIndex.emplace(v, index);
      return index;
    };

    // Points: one per sector of kept faces around each vertex, sectors being
    // separated by order-0 constrained edges (and by non-kept faces).
    ReceiverMesh& mesh = out.Mesh;
    auto isCut = [&](Face f, int edge) {
      const int label = f->info().Label[edge];
      return label >= 0 && this->Labels[label].Order == 0;
    };
    for (Face f : cdt.finite_face_handles())
    {
      for (int i = 0; i < 3; ++i)
      {
        f->info().Point[i] = -1;
      }
    }
    for (Face f : cdt.finite_face_handles())
    {
      if (!f->info().Kept)
      {
        continue;
      }
      for (int i = 0; i < 3; ++i)
      {
        if (f->info().Point[i] >= 0)
        {
          continue;
        }
        VertexHandle v = f->vertex(i);
        const int geometric = vertexOf(v);
        // Rotate clockwise from f to the start of its sector (or all the way
        // round when nothing separates).
        Face first = f;
        for (;;)
        {
          // The face clockwise around v shares the edge opposite cw(j).
          const int edge = Cw(first->index(v));
          Face prev = first->neighbor(edge);
          if (isCut(first, edge) || cdt.is_infinite(prev) || !prev->info().Kept || prev == f)
          {
            break;
          }
          first = prev;
        }
        const int point = static_cast<int>(mesh.Points.size());
        mesh.Points.push_back(vertex3[geometric]);
        mesh.PointVertex.push_back(geometric);
        // Sweep counter-clockwise from the sector start, assigning the point.
        Face g = first;
        for (;;)
        {
          const int j = g->index(v);
          g->info().Point[j] = point;
          const int edge = Ccw(j);
          Face next = g->neighbor(edge);
          if (isCut(g, edge) || cdt.is_infinite(next) || !next->info().Kept ||
            next->info().Point[next->index(v)] >= 0)
          {
            break;
          }
          g = next;
        }
      }
    }

    for (Face f : cdt.finite_face_handles())
    {
      if (!f->info().Kept)
      {
        if (f->info().State == 3)
        {
          out.RemovedArea += TriangleArea3(vertex3[vertexOf(f->vertex(0))],
            vertex3[vertexOf(f->vertex(1))], vertex3[vertexOf(f->vertex(2))]);
        }
        continue;
      }
      const std::array<int, 3> t = { f->info().Point[0], f->info().Point[1], f->info().Point[2] };
      if (!(TriangleArea3(mesh.Points[t[0]], mesh.Points[t[1]], mesh.Points[t[2]]) > 0.0))
      {
        ++out.DroppedDegenerate;
        continue;
      }
      mesh.Triangles.push_back(t);
    }

    // Constrained edges bordering a kept face, with their labels.
    for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
    {
      Face f = e->first;
      const int i = e->second;
      const int label = f->info().Label[i];
      if (label < 0)
      {
        continue;
      }
      // In a face, the edge opposite vertex i runs counter-clockwise from
      // vertex ccw(i) to cw(i): that face is on its left.
      Face left = f;
      int li = i;
      if (cdt.is_infinite(f) || !f->info().Kept)
      {
        left = f->neighbor(i);
        li = left->index(f);
      }
      if (cdt.is_infinite(left) || !left->info().Kept)
      {
        continue;
      }
      DiscontinuitySegment s;
      s.Order = this->Labels[label].Order;
      s.SourceId = this->Labels[label].SourceId;
      s.ReceiverId = input.ReceiverId;
      s.PointA = left->info().Point[Ccw(li)];
      s.PointB = left->info().Point[Cw(li)];
      s.A = mesh.Points[s.PointA];
      s.B = mesh.Points[s.PointB];
      mesh.Segments.push_back(s);
    }
  }
};

} // namespace

TriangulationOutput TriangulateReceiver(const TriangulationInput& input)
{
  TriangulationOutput out;
  out.Mesh.ReceiverId = input.ReceiverId;
  std::map<std::pair<double, double>, int> known;
  for (std::size_t k = 0; k < input.Known2D.size(); ++k)
  {
    known.emplace(std::make_pair(input.Known2D[k][0], input.Known2D[k][1]), static_cast<int>(k));
  }

  Stage<cgal::ExactCDT> exact;
  exact.Insert(input.Constraints, known, out.Failures);
  exact.Label();
  exact.Classify();
  if (!(input.MinimumAngle > 0.0))
  {
    exact.Extract(input, out);
    return out;
  }

  // Refinement: the exact arrangement rounded to doubles, refined where kept.
  const std::vector<Constraint2D> arrangement = exact.Arrangement();
  Stage<cgal::RefineCDT> refine;
  refine.Insert(arrangement, known, out.Failures);
  refine.Label();
  refine.Classify();
  for (auto f : refine.Cdt.all_face_handles())
  {
    f->set_in_domain(!refine.Cdt.is_infinite(f) && f->info().Kept);
  }
  const double s = std::sin(input.MinimumAngle * M_PI / 180.0);
  cgal::RefineMesher mesher(refine.Cdt, cgal::RefineCriteria(s * s, 0.0));
  mesher.init(true);
  mesher.refine_mesh();
  // The mesher splits constrained edges; CDT+ keeps their constraint ids, so
  // labelling again recovers every label.
  refine.Label();
  refine.Classify();
  refine.Extract(input, out);
  return out;
}

} // namespace detail
} // namespace penumbra
