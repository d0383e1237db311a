# SPDX-License-Identifier: GPL-3.0-or-later
"""Pictures of Penumbra scenes and solutions.

Debian's VTK renders only through X. `render_png` therefore renders in this
process when a display is available and otherwise re-runs itself under
`xvfb-run` in a child process, so that a missing display is an error message
and never an abort of the caller.
"""
import os
import shutil
import subprocess
import sys

# The camera of the Cornell box data set (metres): eye, focal point, view up,
# vertical view angle from a 35 mm lens on 25 mm film.
CORNELL_CAMERA = {
    "position": (0.278, 0.273, -0.800),
    "focal_point": (0.278, 0.273, 0.0),
    "view_up": (0.0, 1.0, 0.0),
    "view_angle": 39.3076,  # 2 atan(12.5 / 35) in degrees
}


class RenderError(RuntimeError):
    """The picture could not be made (no display, no xvfb-run, ...)."""


def _has_display():
    return bool(os.environ.get("DISPLAY"))


#: Vertical field of view (degrees) inside rooms and for explicit cameras: a
#: room photographer's wide lens (about 24 mm on full frame, horizontally).
INTERIOR_VIEW_ANGLE = 70.0


def parse_camera(spec):
    """A camera from its command-line form: "auto", "cornell", or a dict
    {"position", "focal_point", "view_up"} from "X,Y,Z:FX,FY,FZ[:UX,UY,UZ]"
    (view up +y when left out). Raises ValueError naming what is wrong."""
    import math

    if spec in ("auto", "cornell"):
        return spec
    if isinstance(spec, dict):
        return spec
    parts = str(spec).split(":")
    if len(parts) not in (2, 3):
        raise ValueError("expected auto, cornell or X,Y,Z:FX,FY,FZ[:UX,UY,UZ], got '%s'" % spec)
    names = ("eye", "focal point", "view up")
    vectors = []
    for name, part in zip(names, parts):
        try:
            vector = tuple(float(v) for v in part.split(","))
        except ValueError:
            raise ValueError("the %s '%s' is not three numbers" % (name, part)) from None
        if len(vector) != 3 or not all(math.isfinite(v) for v in vector):
            raise ValueError("the %s '%s' is not three finite numbers" % (name, part))
        vectors.append(vector)
    if len(vectors) == 2:
        vectors.append((0.0, 1.0, 0.0))
    eye, focal, up = vectors
    direction = [f - e for f, e in zip(focal, eye)]
    if math.sqrt(sum(d * d for d in direction)) == 0.0:
        raise ValueError("the eye and the focal point coincide")
    cross = (direction[1] * up[2] - direction[2] * up[1], direction[2] * up[0] -
             direction[0] * up[2], direction[0] * up[1] - direction[1] * up[0])
    if math.sqrt(sum(c * c for c in cross)) == 0.0:
        raise ValueError("the view up %s is parallel to the view direction" % (up,))
    return {"position": eye, "focal_point": focal, "view_up": up}


def render_png(vtp_path, png_path, camera="auto", size=(512, 512), exposure=None, fov=None):
    """Render the .vtp at `vtp_path` into `png_path`.

    camera: "auto" (inside a closed room: from the room, looking at its most
    lit wall; otherwise from outside, framing the data), "cornell" for the
    Cornell box camera, or "X,Y,Z:FX,FY,FZ[:UX,UY,UZ]" (see parse_camera).
    fov: vertical view angle in degrees (default INTERIOR_VIEW_ANGLE inside
    rooms and for explicit cameras, VTK's 30 from outside).
    exposure: radiance mapped to white; None picks the 99th percentile.
    Raises RenderError when no display can be had.
    """
    if isinstance(camera, dict):
        camera = "%s:%s:%s" % tuple(",".join(repr(float(v)) for v in camera[k])
                                    for k in ("position", "focal_point", "view_up"))
    parse_camera(camera)
    if _has_display():
        _render_here(vtp_path, png_path, camera, size, exposure, fov)
        return
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        raise RenderError("no X display and no xvfb-run: install the 'xvfb' and 'xauth' "
                          "packages or set DISPLAY to render a picture")
    command = [xvfb, "-a", sys.executable, "-m", "penumbra", "render", vtp_path,
               "-o", png_path, "--camera", camera, "--size", str(size[0]), str(size[1])]
    if exposure is not None:
        command += ["--exposure", repr(float(exposure))]
    if fov is not None:
        command += ["--fov", repr(float(fov))]
    env = dict(os.environ)
    package_root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = os.pathsep.join(
        [package_root] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    result = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            universal_newlines=True)
    if result.returncode != 0:
        raise RenderError("rendering under xvfb-run failed: %s"
                          % (result.stderr.strip().splitlines() or ["(no message)"])[-1])


def default_exposure(radiance, weights=None):
    """The 99th percentile of the channel maxima of an (n, 3) radiance array,
    weighted by `weights` (e.g. the area each point stands for); 1 if empty."""
    import numpy as np

    radiance = np.asarray(radiance, dtype=float).reshape(-1, 3)
    peaks = radiance.max(axis=1) if len(radiance) else np.zeros(1)
    w = np.ones(len(peaks)) if weights is None else np.asarray(weights, dtype=float)
    order = np.argsort(peaks)
    cumulative = np.cumsum(w[order])
    if not len(peaks) or cumulative[-1] <= 0:
        return 1.0
    return float(peaks[order][np.searchsorted(cumulative, 0.99 * cumulative[-1])])


def radiance_to_colors(radiance, exposure=None, weights=None):
    """Display colors (uint8 RGB) for an (n, 3) radiance array.

    Linear radiance is divided by `exposure` (default: the 99th percentile of
    the channel maxima, weighted by `weights` -- e.g. the area each point
    stands for, so that densely sampled lights do not set the exposure --
    so highlights do not wash out the picture), clipped to [0, 1] and
    encoded with the sRGB transfer curve.
    """
    import numpy as np

    radiance = np.asarray(radiance, dtype=float).reshape(-1, 3)
    if exposure is None:
        exposure = default_exposure(radiance, weights)
    exposure = exposure if exposure > 0 else 1.0
    x = np.clip(radiance / exposure, 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(srgb * 255.0).astype(np.uint8)


def _actor(data, exposure=None):
    """An actor showing `data`: a solution (point array `Radiance`) unlit, as
    computed, through `radiance_to_colors`; a bare scene in its reflectance
    colors (emitters white) for a headlight. Returns (actor, objects to keep
    alive)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (the OpenGL mapper, before any mapper)

    shaded = data.NewInstance()
    shaded.ShallowCopy(data)
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(shaded)
    actor = vtkActor()
    actor.SetMapper(mapper)
    radiance = data.GetPointData().GetArray("Radiance")
    if radiance is not None:
        # View-independent radiance is the picture: show it unlit.
        colors = numpy_to_vtk(radiance_to_colors(vtk_to_numpy(radiance), exposure,
                                                 _point_areas(data)), deep=1)
        colors.SetName("DisplayColor")
        shaded.GetPointData().AddArray(colors)
        mapper.SetScalarModeToUsePointFieldData()
        actor.GetProperty().LightingOff()
    else:
        reflectance = vtk_to_numpy(data.GetCellData().GetArray("Reflectance"))
        emission = vtk_to_numpy(data.GetCellData().GetArray("Emission"))
        rgb = np.where(emission.max(axis=1, keepdims=True) > 0, 1.0, reflectance)
        colors = numpy_to_vtk(np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8), deep=1)
        colors.SetName("DisplayColor")
        shaded.GetCellData().AddArray(colors)
        mapper.SetScalarModeToUseCellFieldData()
        # Walls seen edge-on from a headlight would be black: mostly ambient.
        actor.GetProperty().SetAmbient(0.6)
        actor.GetProperty().SetDiffuse(0.4)
    mapper.SelectColorArray("DisplayColor")
    mapper.SetColorModeToDirectScalars()
    mapper.ScalarVisibilityOn()
    return actor, (shaded, mapper)


def _window(size):
    from vtkmodules.vtkRenderingCore import vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (registers the OpenGL backend)

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(int(size[0]), int(size[1]))
    return window


def _triangles(data):
    """(points, triangles, surface ids) of the polygons of `data`, triangulated
    (fan; scene polygons are planar and the fans only feed ray tests and area
    sums); a result's triangles are taken as they are."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points = vtk_to_numpy(data.GetPoints().GetData()).astype(float)
    cells = vtk_to_numpy(data.GetPolys().GetData())
    ids = data.GetCellData().GetArray("SurfaceId")
    offset = data.GetNumberOfVerts() + data.GetNumberOfLines()
    count = data.GetNumberOfPolys()
    cell_surface = (vtk_to_numpy(ids)[offset:offset + count] if ids is not None
                    else np.arange(count))
    if len(cells) == 4 * count and (cells[::4] == 3).all():
        return points, cells.reshape(-1, 4)[:, 1:].astype(np.int64), np.asarray(cell_surface)
    triangles, surfaces = [], []
    k = cell = 0
    while k < len(cells):
        n = int(cells[k])
        corners = cells[k + 1:k + 1 + n]
        for j in range(1, n - 1):
            triangles.append((corners[0], corners[j], corners[j + 1]))
            surfaces.append(cell_surface[cell])
        k += n + 1
        cell += 1
    return points, np.array(triangles, dtype=np.int64).reshape(-1, 3), np.array(surfaces)


def _first_hits(locator, origins, directions, reach):
    """The cell first met by each ray (or -1), and its distance."""
    from vtkmodules.vtkCommonCore import mutable

    cells, distances = [], []
    for origin, direction in zip(origins, directions):
        t, x, pcoords, sub, cell = mutable(0.0), [0.0] * 3, [0.0] * 3, mutable(0), mutable(-1)
        target = [o + reach * d for o, d in zip(origin, direction)]
        hit = locator.IntersectWithLine(list(origin), target, 0.0, t, x, pcoords, sub, cell)
        cells.append(int(cell) if hit else -1)
        distances.append(float(t) * reach if hit else float("inf"))
    return cells, distances


def interior_view(data):
    """A camera inside a closed room, or None when `data` is not one.

    A point is inside when nearly every ray from it meets the front of a
    surface (a room's walls face inwards; from outside a box, rays meet backs
    or nothing). Of the points at the middle of the bounding box at three
    heights (+y up), the first inside one is used. The camera looks at the
    wall (a surface facing sideways) with the most reflected light (area times
    mean radiance; reflectance without a solution) from near the opposite wall,
    at that height.
    """
    import numpy as np
    from vtkmodules.vtkCommonDataModel import vtkStaticCellLocator
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from .export import _triangle_polydata

    if data.GetNumberOfPolys() == 0:
        return None
    points, triangles, surfaces = _triangles(data)
    if not len(triangles):
        return None
    normals = np.cross(points[triangles[:, 1]] - points[triangles[:, 0]],
                       points[triangles[:, 2]] - points[triangles[:, 0]])
    areas = 0.5 * np.linalg.norm(normals, axis=1)
    normals = normals / np.maximum(2.0 * areas, 1e-300)[:, None]
    mesh = _triangle_polydata(points, triangles)
    locator = vtkStaticCellLocator()
    locator.SetDataSet(mesh)
    locator.BuildLocator()
    lo, hi = points.min(axis=0), points.max(axis=0)
    reach = 4.0 * float(np.linalg.norm(hi - lo)) + 1e-12
    # Directions spread evenly over the sphere (a Fibonacci lattice).
    count = 64
    k = np.arange(count) + 0.5
    z = 1.0 - 2.0 * k / count
    phi = np.pi * (1.0 + 5.0 ** 0.5) * k
    directions = np.stack([np.sqrt(1 - z * z) * np.cos(phi), z,
                           np.sqrt(1 - z * z) * np.sin(phi)], axis=1)
    eye = None
    for height in (0.5, 0.4, 0.6):
        candidate = np.array([0.5 * (lo[0] + hi[0]), lo[1] + height * (hi[1] - lo[1]),
                              0.5 * (lo[2] + hi[2])])
        cells, _ = _first_hits(locator, [candidate] * count, directions, reach)
        cells = np.array(cells)
        fronts = (cells >= 0) & (np.einsum("ij,ij->i", normals[np.maximum(cells, 0)],
                                           directions) < 0.0)
        if fronts.mean() >= 0.95:
            eye = candidate
            break
    if eye is None:
        return None
    radiance = data.GetPointData().GetArray("Radiance")
    if radiance is not None:
        light = vtk_to_numpy(radiance).sum(axis=1)[triangles].mean(axis=1)
    else:
        reflectance = data.GetCellData().GetArray("Reflectance")
        light = (vtk_to_numpy(reflectance).sum(axis=1)[surfaces] if reflectance is not None
                 else np.ones(len(triangles)))
    sideways = np.abs(normals[:, 1]) < 0.3
    facing = np.einsum("ij,ij->i", normals, eye - points[triangles].mean(axis=1)) > 0.0
    candidates = sideways & facing
    if not candidates.any():
        return None
    scores = {}
    for s in np.unique(surfaces[candidates]):
        mask = candidates & (surfaces == s)
        scores[int(s)] = float(np.sum(areas[mask] * light[mask]))
    wall = max(scores, key=scores.get)
    mask = candidates & (surfaces == wall)
    centre = np.sum(points[triangles[mask]].mean(axis=1) * areas[mask, None], axis=0) \
        / np.sum(areas[mask])
    normal = np.sum(normals[mask] * areas[mask, None], axis=0)
    normal[1] = 0.0
    normal /= max(np.linalg.norm(normal), 1e-300)
    focal = np.array([centre[0], eye[1], centre[2]])
    start = focal + normal * 1e-6 * reach
    _, distance = _first_hits(locator, [start], [normal], reach)
    depth = distance[0] if np.isfinite(distance[0]) else float(np.linalg.norm(eye - focal))
    position = focal + normal * 0.9 * depth
    return {"position": tuple(position), "focal_point": tuple(focal), "view_up": (0.0, 1.0, 0.0)}


def make_render_window(data, camera="auto", size=(512, 512), exposure=None, fov=None):
    """An off-screen vtkRenderWindow showing `data` (a scene or a solution).

    A solution (point array `Radiance`) is shown unlit, as computed, through
    `radiance_to_colors`; a bare scene in its reflectance colors (emitters
    white) under a headlight. camera and fov as for `render_png`. Needs an X
    display (see `render_png`).
    """
    from vtkmodules.vtkRenderingCore import vtkRenderer

    actor, keep = _actor(data, exposure)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(0.0, 0.0, 0.0)
    window = _window(size)
    window.AddRenderer(renderer)
    view = renderer.GetActiveCamera()
    camera = parse_camera(camera)
    if camera == "auto":
        camera = interior_view(data) or "auto"
    if camera == "cornell":
        view.SetPosition(*CORNELL_CAMERA["position"])
        view.SetFocalPoint(*CORNELL_CAMERA["focal_point"])
        view.SetViewUp(*CORNELL_CAMERA["view_up"])
        view.SetViewAngle(fov or CORNELL_CAMERA["view_angle"])
        renderer.ResetCameraClippingRange()
    elif isinstance(camera, dict):
        view.SetPosition(*camera["position"])
        view.SetFocalPoint(*camera["focal_point"])
        view.SetViewUp(*camera["view_up"])
        view.SetViewAngle(fov or INTERIOR_VIEW_ANGLE)
        renderer.ResetCameraClippingRange()
    else:
        view.SetPosition(0.6, 0.8, -1.0)
        view.SetFocalPoint(0.0, 0.0, 0.0)
        view.SetViewUp(0.0, 1.0, 0.0)
        if fov:
            view.SetViewAngle(fov)
        renderer.ResetCamera()
        view.Zoom(1.2)
    window._penumbra_keep = keep + (actor, renderer)  # keep the pipeline alive
    return window


def extract_surface(data, surface_id):
    """The cells of `data` (polydata with cell array `SurfaceId`) that belong
    to surface `surface_id`, as polydata (triangles and lines)."""
    from vtkmodules.vtkCommonDataModel import vtkDataObject
    from vtkmodules.vtkFiltersCore import vtkThreshold
    from vtkmodules.vtkFiltersGeometry import vtkGeometryFilter

    threshold = vtkThreshold()
    threshold.SetInputData(data)
    threshold.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_CELLS, "SurfaceId")
    threshold.SetLowerThreshold(surface_id - 0.5)
    threshold.SetUpperThreshold(surface_id + 0.5)
    threshold.SetThresholdFunction(vtkThreshold.THRESHOLD_BETWEEN)
    geometry = vtkGeometryFilter()
    geometry.SetInputConnection(threshold.GetOutputPort())
    geometry.Update()
    return geometry.GetOutput()


def make_comparison_window(solutions, surface_id, size=(800, 400), exposure=None, titles=None,
                           marks=None, mark_size=2.0, mark_color=(1.0, 0.1, 0.1),
                           view_bounds=None):
    """Off-screen window with surface `surface_id` of each solution side by
    side, seen from the front along its normal, all at one exposure (by
    default the first solution's, see `radiance_to_colors`), each captioned
    with its entry of `titles` when given.

    marks: optional, one entry per solution: None or points to mark on that
    panel as dots (an (n, 3) array, or a vtkPolyData whose points are taken;
    e.g. the sample points of a method), `mark_size` pixels wide, in
    `mark_color` (RGB in [0, 1]), drawn just in front of the surface.
    view_bounds: optional (xmin, xmax, ymin, ymax, zmin, zmax): frame this
    box of the surface (a close-up) instead of the whole surface."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkTextActor
    import vtkmodules.vtkRenderingFreeType  # noqa: F401 (text rendering)

    surfaces = [extract_surface(s, surface_id) for s in solutions]
    if any(s.GetNumberOfPolys() == 0 for s in surfaces):
        raise RenderError("surface %d has no triangles in every solution" % surface_id)
    if exposure is None:
        exposure = default_exposure(
            vtk_to_numpy(surfaces[0].GetPointData().GetArray("Radiance")),
            _point_areas(surfaces[0]))
    # The surface's front normal, from its largest triangle.
    points = vtk_to_numpy(surfaces[0].GetPoints().GetData())
    polys = vtk_to_numpy(surfaces[0].GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    normals = np.cross(points[polys[:, 1]] - points[polys[:, 0]],
                       points[polys[:, 2]] - points[polys[:, 0]])
    normal = normals[np.argmax(np.linalg.norm(normals, axis=1))]
    normal = normal / np.linalg.norm(normal)
    up = np.eye(3)[np.argmin(np.abs(normal))]
    up = up - normal * np.dot(up, normal)

    window = _window(size)
    keep = []
    count = len(surfaces)
    for k, surface in enumerate(surfaces):
        actor, objects = _actor(surface, exposure)
        renderer = vtkRenderer()
        renderer.SetViewport(k / count, 0.0, (k + 1) / count, 1.0)
        renderer.AddActor(actor)
        renderer.SetBackground(0.0, 0.0, 0.0)
        view = renderer.GetActiveCamera()
        bounds = surface.GetBounds() if view_bounds is None else tuple(view_bounds)
        center = 0.5 * (np.array(bounds[0::2]) + np.array(bounds[1::2]))
        view.SetFocalPoint(*center)
        view.SetPosition(*(center + normal))
        view.SetViewUp(*up)
        renderer.ResetCamera(*bounds)
        view.Zoom(1.3)  # the reset frames the bounding sphere; fill the viewport
        if marks is not None and marks[k] is not None:
            dots = _dots(marks[k], normal * 1e-3 * surface.GetLength(), mark_size, mark_color)
            renderer.AddActor(dots[0])
            keep += list(dots)
        if titles:
            caption = vtkTextActor()
            caption.SetInput(titles[k])
            caption.GetTextProperty().SetFontSize(max(10, int(size[1]) // 24))
            caption.SetPosition(8, 8)
            renderer.AddActor2D(caption)
            keep.append(caption)
        window.AddRenderer(renderer)
        keep += [actor, renderer, surface] + list(objects)
    window._penumbra_keep = tuple(keep)
    return window


def _dots(points, offset, size, color):
    """An actor drawing `points` ((n, 3) array or a vtkDataSet's points),
    moved by `offset`, as round dots `size` pixels wide. Returns (actor,
    objects to keep alive)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    if hasattr(points, "GetPoints"):
        points = vtk_to_numpy(points.GetPoints().GetData()) if points.GetNumberOfPoints() \
            else np.zeros((0, 3))
    xyz = np.asarray(points, dtype=float).reshape(-1, 3) + np.asarray(offset, dtype=float)
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(xyz, deep=1))
    verts = vtkCellArray()
    for k in range(len(xyz)):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(k)
    data = vtkPolyData()
    data.SetPoints(vtk_points)
    data.SetVerts(verts)
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(data)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetColor(*color)
    prop.SetPointSize(size)
    prop.RenderPointsAsSpheresOn()
    prop.LightingOff()
    return actor, (data, mapper)


def save_window_png(window, png_path, size=None):
    """Render `window` and write it to `png_path`, shrunk to `size` (width,
    height; default: the window's size) with a resampling filter: render the
    window at a multiple of `size` for anti-aliasing that Xvfb's OpenGL lacks."""
    from vtkmodules.vtkImagingCore import vtkImageResize
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    window.Render()
    grabber = vtkWindowToImageFilter()
    grabber.SetInput(window)
    grabber.ReadFrontBufferOff()
    shrink = vtkImageResize()
    shrink.SetInputConnection(grabber.GetOutputPort())
    width, height = size if size is not None else window.GetSize()
    shrink.SetOutputDimensions(int(width), int(height), 1)
    writer = vtkPNGWriter()
    writer.SetFileName(png_path)
    writer.SetInputConnection(shrink.GetOutputPort())
    writer.Write()


def _point_areas(data):
    """The area each point stands for: a third of its triangles' areas."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    points = vtk_to_numpy(data.GetPoints().GetData())
    areas = np.zeros(len(points))
    polys = vtk_to_numpy(data.GetPolys().GetData())
    if len(polys) and len(polys) % 4 == 0 and (polys[::4] == 3).all():
        triangles = polys.reshape(-1, 4)[:, 1:]
        a, b, c = (points[triangles[:, k]] for k in range(3))
        area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
        for k in range(3):
            np.add.at(areas, triangles[:, k], area / 3.0)
    else:
        areas[:] = 1.0
    return areas


def _render_here(vtp_path, png_path, camera, size, exposure, fov=None):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(vtp_path)
    reader.Update()
    data = reader.GetOutput()
    if data.GetNumberOfCells() == 0:
        raise RenderError("nothing to render in %s" % vtp_path)
    # Render at 3x and filter down: anti-aliasing that Xvfb's OpenGL lacks
    # (edges of faces seen at grazing angles would look dotted).
    supersampling = 3
    window = make_render_window(data, camera, [supersampling * n for n in size], exposure, fov)
    save_window_png(window, png_path, size)
    window.Finalize()
