// SPDX-License-Identifier: GPL-3.0-or-later
// The only CGAL translation unit of the core: one receiver's constrained
// Delaunay triangulation for the discontinuity mesher, and its refinement by
// point insertion for the adaptive sampler (see penumbraReceiverTriangulation.h).
#include "penumbraReceiverTriangulation.h"

#include "penumbraCGAL.h"
#include "penumbraMath.h"

#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/property_map.h>
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

/// Give copy `point` of vertex `v` to the sector of kept faces around v that
/// contains `f`: rotate clockwise to the sector's start (a cut edge, the hull
/// or an unkept face; all the way round when nothing separates), then sweep
/// counter-clockwise assigning the point until the sector ends.
template <typename Triangulation, typename Face, typename VertexHandle, typename IsCut>
void AssignSector(
  const Triangulation& cdt, Face f, VertexHandle v, int point, const IsCut& isCut)
{
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
        const int point = static_cast<int>(mesh.Points.size());
        mesh.Points.push_back(vertex3[geometric]);
        mesh.PointVertex.push_back(geometric);
        AssignSector(cdt, f, v, point, isCut);
      }
    }

    for (Face f : cdt.finite_face_handles())
    {
      if (!f->info().Kept)
      {
        if (f->info().State == 3)
        {
          // Indices first: vertexOf may grow vertex3, which would invalidate
          // a reference taken into it before the next call.
          const int a = vertexOf(f->vertex(0));
          const int b = vertexOf(f->vertex(1));
          const int c = vertexOf(f->vertex(2));
          out.RemovedArea += TriangleArea3(vertex3[a], vertex3[b], vertex3[c]);
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
  const double s = std::sin(input.MinimumAngle * Pi / 180.0);
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


//------------------------------------------------------------------------------
// RefinableTriangulation
//------------------------------------------------------------------------------
struct RefinableTriangulation::Internals
{
  using CDT = cgal::RefineCDT;
  using Face = CDT::Face_handle;
  using VertexHandle = CDT::Vertex_handle;
  using Point = CDT::Point;

  CDT Cdt;
  std::vector<VertexHandle> Vertices;           // by id
  std::map<CDT::Constraint_id, int> ConstraintOf; // input segment of each constraint
  std::vector<RefinableSegment> Segments;       // input labels
  std::size_t Irregularities = 0;

  int AddId(VertexHandle v)
  {
    v->info().Id = static_cast<int>(this->Vertices.size());
    this->Vertices.push_back(v);
    return v->info().Id;
  }

  // Label of the constrained edge (f, i): lowest order of the input segments
  // through it (-1 lowest), then lowest source id.
  void EdgeLabel(Face f, int i, int& order, int& source) const
  {
    const VertexHandle va = f->vertex(Ccw(i)), vb = f->vertex(Cw(i));
    int rank = 1 << 30;
    order = 2;
    source = -1;
    for (auto ctx : this->Cdt.contexts(va, vb))
    {
      auto found = this->ConstraintOf.find(ctx.id());
      if (found == this->ConstraintOf.end())
      {
        continue;
      }
      const RefinableSegment& s = this->Segments[found->second];
      const int r = s.Order == -1 ? 0 : s.Order + 1;
      if (r < rank || (r == rank && s.SourceId < source))
      {
        rank = r;
        order = s.Order;
        source = s.SourceId;
      }
    }
  }

  // Mark the faces incident to v kept or not: all `kept` after a point
  // inserted in a face or an unconstrained edge; after splitting a
  // constrained edge a-b, each face takes the flag of the old face on its
  // side of the line (exact orientation of its vertices off the line).
  void MarkAround(VertexHandle v, bool kept)
  {
    auto fc = this->Cdt.incident_faces(v), done = fc;
    do
    {
      fc->info().Kept = kept && !this->Cdt.is_infinite(fc);
    } while (++fc != done);
  }
  void MarkAroundSplit(VertexHandle v, const Point& a, const Point& b, bool keptLeft,
    bool keptRight)
  {
    auto fc = this->Cdt.incident_faces(v), done = fc;
    do
    {
      if (this->Cdt.is_infinite(fc))
      {
        fc->info().Kept = false;
        continue;
      }
      int left = 0, right = 0;
      for (int k = 0; k < 3; ++k)
      {
        if (fc->vertex(k) == v)
        {
          continue;
        }
        const CGAL::Orientation o = CGAL::orientation(a, b, fc->vertex(k)->point());
        left += o == CGAL::LEFT_TURN;
        right += o == CGAL::RIGHT_TURN;
      }
      bool onLeft = left > right;
      if (left == right)
      {
        // Not expected (a face cannot straddle the constrained line at v):
        // decide by the centroid.
        const Point c = CGAL::centroid(fc->vertex(0)->point(), fc->vertex(1)->point(),
          fc->vertex(2)->point());
        onLeft = CGAL::orientation(a, b, c) == CGAL::LEFT_TURN;
      }
      fc->info().Kept = onLeft ? keptLeft : keptRight;
    } while (++fc != done);
  }
};

RefinableTriangulation::RefinableTriangulation(const std::vector<P2>& vertices,
  const std::vector<RefinableSegment>& segments, const std::vector<P2>& keptSeeds)
  : Internal(new Internals)
{
  using Point = Internals::Point;
  using VertexHandle = Internals::VertexHandle;
  using Face = Internals::Face;
  Internals& in = *this->Internal;
  in.Segments = segments;
  const int n = static_cast<int>(vertices.size());

  // A far bounding square: receiver edges are then never on the convex hull,
  // so a point rounded slightly outside an outline edge can still split it.
  double lo[2] = { 0.0, 0.0 }, hi[2] = { 0.0, 0.0 };
  for (int i = 0; i < n; ++i)
  {
    for (int c = 0; c < 2; ++c)
    {
      lo[c] = i == 0 ? vertices[i][c] : std::min(lo[c], vertices[i][c]);
      hi[c] = i == 0 ? vertices[i][c] : std::max(hi[c], vertices[i][c]);
    }
  }
  const double size = std::max({ hi[0] - lo[0], hi[1] - lo[1], 1e-300 });
  const double cx = 0.5 * (lo[0] + hi[0]), cy = 0.5 * (lo[1] + hi[1]);
  for (int k = 0; k < 4; ++k)
  {
    const double sx = (k == 0 || k == 3) ? -4.0 : 4.0, sy = k < 2 ? -4.0 : 4.0;
    in.Cdt.insert(Point(cx + sx * size, cy + sy * size))->info().Id = cgal::BoundingCornerId;
  }

  // Vertices in spatial (Hilbert) order, each located from the previous one.
  std::vector<Point> points;
  points.reserve(n);
  for (const auto& v : vertices)
  {
    points.emplace_back(v[0], v[1]);
  }
  std::vector<std::size_t> order(n);
  for (int i = 0; i < n; ++i)
  {
    order[i] = static_cast<std::size_t>(i);
  }
  using SortTraits = CGAL::Spatial_sort_traits_adapter_2<cgal::RefineKernel,
    CGAL::Pointer_property_map<Point>::type>;
  CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(points)));
  in.Vertices.assign(n, VertexHandle());
  VertexHandle hint;
  for (std::size_t i : order)
  {
    hint = in.Cdt.insert(points[i], hint == VertexHandle() ? Face() : hint->face());
    if (hint->info().Id >= 0 || hint->info().Id == cgal::BoundingCornerId)
    {
      ++in.Irregularities; // coincides with another vertex
    }
    else
    {
      hint->info().Id = static_cast<int>(i);
    }
    in.Vertices[i] = hint;
  }
  for (std::size_t k = 0; k < segments.size(); ++k)
  {
    const RefinableSegment& s = segments[k];
    if (s.A < 0 || s.A >= n || s.B < 0 || s.B >= n || in.Vertices[s.A] == in.Vertices[s.B])
    {
      ++in.Irregularities;
      continue;
    }
    try
    {
      in.ConstraintOf.emplace(in.Cdt.insert_constraint(in.Vertices[s.A], in.Vertices[s.B]),
        static_cast<int>(k));
    }
    catch (const std::exception&)
    {
      ++in.Irregularities;
    }
  }
  // Vertices created where constraints cross (none for a planar input).
  for (auto v = in.Cdt.finite_vertices_begin(); v != in.Cdt.finite_vertices_end(); ++v)
  {
    if (v->info().Id == -1)
    {
      in.AddId(v);
      ++in.Irregularities;
    }
  }

  // Kept cells: flood fill across unconstrained edges from the faces holding
  // the kept triangles' centroids. A cell that reaches the far bounding
  // square lies outside the receiver (the centroid of a sliver along the
  // outline can round across it): it is not kept, since its corners have no
  // vertex id.
  for (Face f : in.Cdt.all_face_handles())
  {
    f->info().Kept = false;
  }
  auto outside = [&](Face f) {
    if (in.Cdt.is_infinite(f))
    {
      return true;
    }
    for (int i = 0; i < 3; ++i)
    {
      if (f->vertex(i)->info().Id == cgal::BoundingCornerId)
      {
        return true;
      }
    }
    return false;
  };
  std::vector<Face> cell;
  Face previous;
  for (const auto& seed : keptSeeds)
  {
    Internals::CDT::Locate_type lt;
    int li = 0;
    Face f = in.Cdt.locate(Point(seed[0], seed[1]), lt, li, previous);
    previous = f;
    // A seed may lie on an unconstrained edge (the centroids of a
    // rectangle's two triangles lie on its other diagonal): both faces of
    // that edge are in the seed's cell.
    if (!(lt == Internals::CDT::FACE || (lt == Internals::CDT::EDGE && !f->is_constrained(li))) ||
      f->info().Kept)
    {
      continue;
    }
    if (outside(f))
    {
      ++in.Irregularities;
      continue;
    }
    cell.assign(1, f);
    f->info().Kept = true;
    bool open = false;
    for (std::size_t next = 0; next < cell.size(); ++next)
    {
      const Face c = cell[next];
      for (int i = 0; i < 3; ++i)
      {
        Face g = c->neighbor(i);
        if (c->is_constrained(i) || g->info().Kept)
        {
          continue;
        }
        if (outside(g))
        {
          open = true;
          continue;
        }
        g->info().Kept = true;
        cell.push_back(g);
      }
    }
    if (open)
    {
      for (Face c : cell)
      {
        c->info().Kept = false;
      }
      ++in.Irregularities;
    }
  }
}

RefinableTriangulation::~RefinableTriangulation() = default;

int RefinableTriangulation::GetNumberOfVertices() const
{
  return static_cast<int>(this->Internal->Vertices.size());
}

P2 RefinableTriangulation::GetVertex(int id) const
{
  const auto& p = this->Internal->Vertices[id]->point();
  return { p.x(), p.y() };
}

std::size_t RefinableTriangulation::GetIrregularities() const
{
  return this->Internal->Irregularities;
}

int RefinableTriangulation::InsertInFace(double u, double v, int hintVertex)
{
  Internals& in = *this->Internal;
  using CDT = Internals::CDT;
  const Internals::Point p(u, v);
  CDT::Locate_type lt;
  int li = 0;
  const Internals::Face start = hintVertex >= 0 && hintVertex < static_cast<int>(in.Vertices.size())
    ? in.Vertices[hintVertex]->face()
    : Internals::Face();
  Internals::Face f = in.Cdt.locate(p, lt, li, start);
  if (in.Cdt.is_infinite(f) || !f->info().Kept ||
    !(lt == CDT::FACE || (lt == CDT::EDGE && !f->is_constrained(li))))
  {
    return -1;
  }
  Internals::VertexHandle vh = in.Cdt.insert(p, lt, f, li);
  in.MarkAround(vh, true);
  return in.AddId(vh);
}

int RefinableTriangulation::InsertOnEdge(int a, int b, double u, double v)
{
  Internals& in = *this->Internal;
  using CDT = Internals::CDT;
  const int n = static_cast<int>(in.Vertices.size());
  if (a < 0 || a >= n || b < 0 || b >= n)
  {
    return -1;
  }
  Internals::Face f;
  int i = 0;
  if (!in.Cdt.is_edge(in.Vertices[a], in.Vertices[b], f, i))
  {
    return -1;
  }
  const Internals::Point m(u, v);
  // Orient the edge as in f (f on its left): pa = vertex ccw(i), pb = cw(i).
  const Internals::Point pa = f->vertex(Ccw(i))->point(), pb = f->vertex(Cw(i))->point();
  const Internals::Face g = f->neighbor(i);
  if (in.Cdt.is_infinite(f) || in.Cdt.is_infinite(g))
  {
    return -1;
  }
  // m strictly between the end points, and the four new triangles keep the
  // orientation of the two old ones (exact predicates on the rounded m).
  const double du = pb.x() - pa.x(), dv = pb.y() - pa.y();
  const double t = ((u - pa.x()) * du + (v - pa.y()) * dv) / (du * du + dv * dv);
  if (!(t > 0.0 && t < 1.0) || m == pa || m == pb)
  {
    return -1;
  }
  const Internals::Point c = f->vertex(i)->point(), d = g->vertex(g->index(f))->point();
  if (CGAL::orientation(pa, m, c) != CGAL::LEFT_TURN ||
    CGAL::orientation(m, pb, c) != CGAL::LEFT_TURN ||
    CGAL::orientation(pa, m, d) != CGAL::RIGHT_TURN ||
    CGAL::orientation(m, pb, d) != CGAL::RIGHT_TURN)
  {
    return -1;
  }
  const bool constrained = f->is_constrained(i);
  const bool keptLeft = f->info().Kept, keptRight = g->info().Kept;
  if (!keptLeft && !keptRight)
  {
    return -1;
  }
  Internals::VertexHandle vh = in.Cdt.insert(m, CDT::EDGE, f, i);
  if (constrained)
  {
    in.MarkAroundSplit(vh, pa, pb, keptLeft, keptRight);
  }
  else
  {
    in.MarkAround(vh, keptLeft || keptRight);
  }
  return in.AddId(vh);
}

void RefinableTriangulation::Extract(RefinableSnapshot& out)
{
  Internals& in = *this->Internal;
  using Face = Internals::Face;
  using VertexHandle = Internals::VertexHandle;
  auto& cdt = in.Cdt;
  out = RefinableSnapshot();
  out.Vertices.resize(in.Vertices.size());
  for (std::size_t k = 0; k < in.Vertices.size(); ++k)
  {
    const auto& p = in.Vertices[k]->point();
    out.Vertices[k] = { p.x(), p.y() };
  }

  // Labels of constrained edges (Label[i] = index into orders/sources).
  std::vector<int> orders, sources;
  for (Face f : cdt.all_face_handles())
  {
    for (int i = 0; i < 3; ++i)
    {
      f->info().Label[i] = -1;
      f->info().Point[i] = -1;
    }
    f->info().State = -1;
  }
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
  {
    Face f = e->first;
    const int i = e->second;
    if (!f->is_constrained(i))
    {
      continue;
    }
    Face g = f->neighbor(i);
    if (!f->info().Kept && !g->info().Kept)
    {
      continue;
    }
    int order = 2, source = -1;
    in.EdgeLabel(f, i, order, source);
    const int index = static_cast<int>(orders.size());
    orders.push_back(order);
    sources.push_back(source);
    f->info().Label[i] = index;
    g->info().Label[g->index(f)] = index;
  }
  auto isCut = [&](Face f, int edge) {
    const int label = f->info().Label[edge];
    return label >= 0 && orders[label] == 0;
  };

  // Points: one per sector of kept faces around each vertex (as in
  // Stage::Extract).
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
      const int point = static_cast<int>(out.PointVertex.size());
      out.PointVertex.push_back(v->info().Id);
      AssignSector(cdt, f, v, point, isCut);
    }
  }

  // Triangles (State = triangle index).
  for (Face f : cdt.finite_face_handles())
  {
    if (!f->info().Kept)
    {
      continue;
    }
    f->info().State = static_cast<int>(out.Triangles.size());
    out.Triangles.push_back({ f->info().Point[0], f->info().Point[1], f->info().Point[2] });
    out.TriangleSegments.push_back({ -1, -1, -1 });
  }

  // Constrained edges bordering a kept face. In a face, edge k (corner k to
  // k + 1) is the edge opposite vertex k + 2.
  for (auto e = cdt.finite_edges_begin(); e != cdt.finite_edges_end(); ++e)
  {
    Face f = e->first;
    const int i = e->second;
    const int label = f->info().Label[i];
    if (label < 0)
    {
      continue;
    }
    Face g = f->neighbor(i);
    const int gi = g->index(f);
    RefinableSnapshot::Segment s;
    s.VertexA = f->vertex(Ccw(i))->info().Id;
    s.VertexB = f->vertex(Cw(i))->info().Id;
    s.Order = orders[label];
    s.SourceId = sources[label];
    const int index = static_cast<int>(out.Segments.size());
    if (f->info().Kept)
    {
      s.LeftA = f->info().Point[Ccw(i)];
      s.LeftB = f->info().Point[Cw(i)];
      out.TriangleSegments[f->info().State][Ccw(i)] = index;
    }
    if (g->info().Kept)
    {
      // In g the edge runs from B (ccw(gi)) to A (cw(gi)).
      s.RightB = g->info().Point[Ccw(gi)];
      s.RightA = g->info().Point[Cw(gi)];
      out.TriangleSegments[g->info().State][Ccw(gi)] = index;
    }
    out.Segments.push_back(s);
  }
}
} // namespace detail
} // namespace penumbra
