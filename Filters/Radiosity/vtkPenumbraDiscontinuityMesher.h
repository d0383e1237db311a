// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkPenumbraDiscontinuityMesher
 * @brief   Discontinuity meshing of every receiving surface (paper §4).
 *
 * Input: a scene (see vtkPenumbraSceneValidator for its contract). For every
 * surface (receiver) and every selected shooter, the shadow boundaries that
 * the occluders cast (EV and VE wedges, optionally occluder-occluder EV
 * wedges, each clipped to where it really is a boundary) and the contact
 * lines of occluders touching the receiver become constraints of a
 * constrained Delaunay triangulation of the receiver (CGAL, exact
 * predicates and constructions). The receiver area under a solid standing on
 * it is not meshed. EEE events (curved boundaries of three generic edges)
 * are not generated.
 *
 * Output vtkPolyData:
 * - polys: triangles covering every receiver, cell data `SurfaceId` (the
 *   scene cell), `DiscontinuityOrder` = -2 and `SourceId` = -1 (not edges);
 * - lines: every constrained edge, cell data `DiscontinuityOrder` (0 contact
 *   = value discontinuity, 1 slope discontinuity, 2 second-derivative
 *   discontinuity, -1 surface boundary), `SourceId` (the shooter that casts
 *   it, -1 for boundaries and contacts) and `SurfaceId`;
 * - point data `SurfaceId`. Points along order-0 lines are duplicated, one
 *   copy per side, so that values may jump there;
 * - field data with the counts of the run: `SegmentsGenerated`,
 *   `SegmentsKept`, `ContactSegments`, `CoverSegments`, `Constraints`, `ConstraintFailures`,
 *   `Triangles`, `Wedges` (wedges traced, after culling).
 *
 * Receivers are meshed in parallel with vtkSMPTools; the output does not
 * depend on the number of threads.
 *
 * @sa vtkPenumbraRadianceEvaluator vtkPenumbraSceneValidator
 */
#ifndef vtkPenumbraDiscontinuityMesher_h
#define vtkPenumbraDiscontinuityMesher_h

#include "vtkPenumbraFiltersModule.h" // for export macro
#include "vtkPenumbraAlgorithm.h"

#include <vector> // for std::vector

class vtkIdList;

class VTKPENUMBRAFILTERS_EXPORT vtkPenumbraDiscontinuityMesher : public vtkPenumbraAlgorithm
{
public:
  static vtkPenumbraDiscontinuityMesher* New();
  vtkTypeMacro(vtkPenumbraDiscontinuityMesher, vtkPenumbraAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The shooters: scene cell ids. Empty (the default) selects every emitter
   * whose power is at least ShooterPowerFraction of the total emitted power.
   * A shooter added with `receivers` (scene cell ids, not empty) traces its
   * boundaries on those receivers only, e.g. a secondary shooter on the
   * receivers whose light it dominates; without, on every receiver. An id
   * that is not a scene cell is an error.
   */
  void AddShooterId(vtkIdType id);
  void AddShooterId(vtkIdType id, vtkIdList* receivers);
  void RemoveAllShooterIds();
  vtkIdType GetNumberOfShooterIds() const;
  vtkIdType GetShooterId(vtkIdType index) const;
  /// The receivers of shooter entry `index` (none: every receiver).
  void GetShooterReceivers(vtkIdType index, vtkIdList* receivers) const;
  ///@}

  ///@{
  /**
   * With no ShooterIds, skip emitters whose power (mean of the RGB channels)
   * is below this fraction of the total. Default 0, range [0, 1].
   */
  vtkSetClampMacro(ShooterPowerFraction, double, 0.0, 1.0);
  vtkGetMacro(ShooterPowerFraction, double);
  ///@}

  ///@{
  /**
   * Quality refinement: the smallest triangle angle in degrees, keeping every
   * constraint. Default 0 (no refinement), range [0, 20.6] (the largest bound
   * for which refinement is guaranteed to terminate).
   */
  vtkSetClampMacro(MinimumAngle, double, 0.0, 20.6);
  vtkGetMacro(MinimumAngle, double);
  ///@}

  ///@{
  /**
   * Also trace EV events between a vertex of one occluder and an edge of
   * another whose wedge cuts the shooter. Default on.
   */
  vtkSetMacro(OccluderOccluderEvents, bool);
  vtkGetMacro(OccluderOccluderEvents, bool);
  vtkBooleanMacro(OccluderOccluderEvents, bool);
  ///@}

  ///@{
  /**
   * Also trace the EV/VE wedges that do not bound umbra or penumbra (D2
   * boundaries inside a penumbra). Default off.
   */
  vtkSetMacro(InteriorEvents, bool);
  vtkGetMacro(InteriorEvents, bool);
  vtkBooleanMacro(InteriorEvents, bool);
  ///@}

  ///@{
  /**
   * Also trace the lines where the plane of an occluder face cuts the
   * shooter (points in that plane see the face edge-on: a D1 line missed by
   * the EV/VE list) and where the shooter's own plane crosses a receiver.
   * Default on.
   */
  vtkSetMacro(PlaneEvents, bool);
  vtkGetMacro(PlaneEvents, bool);
  vtkBooleanMacro(PlaneEvents, bool);
  ///@}

  ///@{
  /**
   * Contact lines where an occluder touches a receiver (order 0), no mesh
   * under solids standing on a receiver, and lines under covers (polygons
   * close in front of a receiver, such as a fixture hung just below a
   * ceiling: their outline and loops inside it, order 1). Default on.
   */
  vtkSetMacro(Contacts, bool);
  vtkGetMacro(Contacts, bool);
  vtkBooleanMacro(Contacts, bool);
  ///@}

  ///@{
  /**
   * Drop shadow boundaries whose estimated radiance jump, relative to the
   * largest direct radiance the receiver gets (with visibility, at sample
   * points), is below this. Default 0 (keep all), range [0, 1]. Contact
   * lines and the line of a shooter's own plane are always kept. With
   * CullWedges, wedges whose jump is certainly below it are not traced (nor
   * counted in `SegmentsGenerated`).
   */
  vtkSetClampMacro(JumpThreshold, double, 0.0, 1.0);
  vtkGetMacro(JumpThreshold, double);
  ///@}

  ///@{
  /**
   * Distance, relative to the scene size, within which an occluder edge lying
   * in a receiver's plane counts as touching it. Default 1e-6, range
   * [0, 1e-2].
   */
  vtkSetClampMacro(ContactTolerance, double, 0.0, 1e-2);
  vtkGetMacro(ContactTolerance, double);
  ///@}

  ///@{
  /**
   * Cull, before tracing them, the wedges that cannot leave a boundary on the
   * receiver (their plane misses it, or their feature lies outside the shaft
   * between shooter and receiver). The output is the same either way up to
   * rounding; turn off only to check that or to measure the gain. Default on.
   */
  vtkSetMacro(CullWedges, bool);
  vtkGetMacro(CullWedges, bool);
  vtkBooleanMacro(CullWedges, bool);
  ///@}

protected:
  vtkPenumbraDiscontinuityMesher();
  ~vtkPenumbraDiscontinuityMesher() override = default;

  int Execute(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  std::vector<vtkIdType> ShooterIds;
  std::vector<std::vector<vtkIdType>> ShooterReceivers; ///< per entry of ShooterIds
  double ShooterPowerFraction;
  double MinimumAngle;
  bool OccluderOccluderEvents;
  bool InteriorEvents;
  bool PlaneEvents;
  bool Contacts;
  double JumpThreshold;
  double ContactTolerance;
  bool CullWedges;

private:
  vtkPenumbraDiscontinuityMesher(const vtkPenumbraDiscontinuityMesher&) = delete;
  void operator=(const vtkPenumbraDiscontinuityMesher&) = delete;
};

#endif
