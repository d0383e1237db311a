// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraRayCaster.h
 * @brief The scene as one Embree scene, for occlusion rays: single rays,
 * packets and streams, each ignoring the surfaces a query names. Embree's
 * types stay in penumbraRayCaster.cxx.
 */
#ifndef penumbraRayCaster_h
#define penumbraRayCaster_h

#include "penumbraVisibilityModule.h" // for export macro
#include "penumbraScene.h"
#include "penumbraVector.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace penumbra
{

/// A segment to test for occlusion, from Origin to Target.
struct OcclusionRay
{
  Vec3 Origin;
  Vec3 Target;
};

/**
 * The scene's surfaces as one Embree scene, for occlusion queries. Every
 * valid polygon is triangulated (ear clipping in its plane); degenerate
 * polygons are skipped. Build once; every query is const and thread-safe
 * (Embree scenes are safe for concurrent queries).
 */
class PENUMBRAVISIBILITY_EXPORT RayCaster
{
public:
  /// Build the Embree scene of `scene`. Throws std::runtime_error if Embree fails.
  explicit RayCaster(const Scene& scene);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /**
   * Fraction of a segment's length cut from both of its ends before testing
   * it, so that the surfaces at the ends (in single precision) do not block
   * it. Default 1e-5, valid range [0, 0.01]; throws InputError outside.
   * Not thread-safe: set it before querying.
   */
  void SetRelativeOffset(double offset);
  double GetRelativeOffset() const;

  /**
   * Whether the segment from `origin` to `target` (shortened as above) meets
   * a surface other than `ignoreA` and `ignoreB` (surface ids, or -1).
   */
  bool IsOccluded(
    const Vec3& origin, const Vec3& target, int ignoreA = -1, int ignoreB = -1) const;

  /**
   * Test `count` segments; occluded[i] is set to 1 if ray i is blocked by a
   * surface other than `ignoreA`/`ignoreB`, else 0. Returns the number of
   * blocked rays. Rays are traced as packets of 16 (consecutive rays with
   * nearby origins and directions go faster). Thread-safe: call it from
   * several threads on disjoint batches for throughput.
   */
  std::size_t TraceOcclusion(const OcclusionRay* rays, std::size_t count,
    unsigned char* occluded, int ignoreA = -1, int ignoreB = -1) const;

  /**
   * Test the segments from one `origin` to `count` targets (traced as
   * packets of 8); occluded[i] is set to 1 or 0 as in TraceOcclusion.
   * Thread-safe.
   */
  void TraceFrom(const Vec3& origin, const Vec3* targets, int count, unsigned char* occluded,
    int ignoreA = -1, int ignoreB = -1) const;

  /**
   * TraceFrom with one more ignored surface per target: the segment to
   * targets[i] also ignores surface targetSurfaces[i] (-1: none), e.g. the
   * surface the target lies on. Traced as one stream of single rays (many
   * targets spread over the scene: faster than packets). Thread-safe.
   */
  void TraceFrom(const Vec3& origin, const Vec3* targets, const int* targetSurfaces, int count,
    unsigned char* occluded, int ignore) const;

  /**
   * The surface first met by each ray from origins[i] along directions[i]
   * (any length; the ray is unbounded), or -1 where it meets none; hits on
   * surface `ignore` (or -1) do not count. Thread-safe.
   */
  void FindNearest(const Vec3* origins, const Vec3* directions, std::size_t count,
    int* surfaces, int ignore) const;

  /// Number of triangles in the Embree scene.
  int GetNumberOfTriangles() const;

  /// Surface (scene polygon id) of triangle `t`.
  int GetTriangleSurface(int t) const;

  /// The three corners of triangle `t` (double precision, as in the scene).
  void GetTriangle(int t, Vec3 corners[3]) const;

  /// Triangles of surface `surfaceId`: [GetFirstTriangle, GetFirstTriangle + count).
  int GetFirstTriangle(int surfaceId) const;
  int GetNumberOfSurfaceTriangles(int surfaceId) const;

  /// Number of surfaces of the scene given to the constructor.
  int GetNumberOfSurfaces() const;

private:
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

} // namespace penumbra

#endif
