# SPDX-License-Identifier: GPL-3.0-or-later
"""Writing scenes and results: VTK XML (.vtp), glTF 2.0 (.gltf, .glb) and PLY.

`write_result` writes a solution, `write_scene` a scene; both choose the format
by the file's extension and raise `penumbra.PenumbraError` for any other.

A result written as glTF or PLY keeps its triangles (the boundary lines are
dropped) and shows the solution as vertex colours: the radiance divided by an
exposure (the radiance shown as white; by default the area-weighted 99th
percentile that `penumbra render` uses), clipped to [0, 1].

- glTF: `COLOR_0` holds that value linearly, as floats, since glTF defines
  vertex colours as linear (a viewer encodes them to sRGB for display, which
  gives the 8-bit sRGB tone map of `penumbra render`); the material is unlit
  (KHR_materials_unlit) so that viewers show the colours as they are. The
  linear radiance itself is the custom attribute `_RADIANCE` (float RGB), and
  `asset.extras.penumbra` records the exposure. The geometry is written by
  VTK's vtkGLTFWriter, which in VTK 9.1 writes neither colours, custom
  attributes nor .glb: its output is completed here.
- PLY: 8-bit sRGB colours (`red`, `green`, `blue`), what PLY viewers display.

A scene written as glTF has one primitive per run of consecutive polygons of
one material, with Reflectance as baseColorFactor (metallic 0, roughness 1)
and Emission as emissiveFactor, scaled into [0, 1] by
KHR_materials_emissive_strength when a channel exceeds 1, so that
`vtkPenumbraGLTFReader` reads the same surfaces back in the same order, to
single precision in the coordinates. glTF has only triangles: a polygon of more
than three vertices is written as its triangles and read back as that many
surfaces. vtkGLTFWriter writes one material per data set, so scenes are
written by the small writer of this module.

Coordinates are written as they are: glTF's metres and +Y up are assumed.
"""
import base64
import json
import os
import struct

RESULT_EXTENSIONS = (".vtp", ".gltf", ".glb", ".ply")
SCENE_EXTENSIONS = (".vtp", ".gltf", ".glb")

# glTF's enumerations.
_FLOAT, _UNSIGNED_INT = 5126, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


def _extension(path, allowed, what):
    from . import PenumbraError

    extension = os.path.splitext(str(path))[1].lower()
    if extension not in allowed:
        raise PenumbraError("cannot write %s to '%s': unknown extension '%s' (give %s or %s)"
                            % (what, path, extension, ", ".join(allowed[:-1]), allowed[-1]))
    return extension


def check_result_path(path):
    """Raise PenumbraError unless `path` names a format write_result writes."""
    _extension(path, RESULT_EXTENSIONS, "a result")


def check_scene_path(path):
    """Raise PenumbraError unless `path` names a format write_scene writes."""
    _extension(path, SCENE_EXTENSIONS, "a scene")


def write_vtp(polydata, path):
    """VTK XML polydata, binary and zlib-compressed; False if it fails."""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(polydata)
    # Inline (not appended) data: Debian 12's expat security update makes
    # ParaView 5.11 reject large appended sections.
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToZLib()
    return writer.Write() == 1


def write_result(polydata, path, exposure=None):
    """Write a solved result to `path` (.vtp, .gltf, .glb or .ply).

    exposure: for glTF and PLY, the radiance shown as white (default: the
    area-weighted 99th percentile of the radiance, as `penumbra render`).
    Returns the exposure used (None for .vtp). Raises PenumbraError for an
    unknown extension, a result without `Radiance`, or a failed write.
    """
    from . import PenumbraError

    extension = _extension(path, RESULT_EXTENSIONS, "a result")
    if extension == ".vtp":
        if not write_vtp(polydata, path):
            raise PenumbraError("could not write %s" % path)
        return None
    points, triangles, radiance = _result_triangles(polydata)
    if exposure is None:
        # The rule of `penumbra render`, on the same data, for the same picture.
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from .rendering import _point_areas, default_exposure
        exposure = default_exposure(vtk_to_numpy(polydata.GetPointData().GetArray("Radiance")),
                                    _point_areas(polydata))
    exposure = float(exposure) if exposure > 0 else 1.0
    if extension == ".ply":
        _write_ply(points, triangles, radiance, exposure, path)
    else:
        _write_result_gltf(points, triangles, radiance, exposure, path)
    return exposure


def write_scene(polydata, path):
    """Write a scene (polygons with Reflectance and Emission) to .vtp, .gltf or .glb."""
    from . import PenumbraError

    extension = _extension(path, SCENE_EXTENSIONS, "a scene")
    if extension == ".vtp":
        if not write_vtp(polydata, path):
            raise PenumbraError("could not write %s" % path)
        return
    _write_scene_gltf(polydata, path)


def _result_triangles(polydata):
    """The result's triangles with only the points they use: float64 points
    (n, 3), int triangles (m, 3) and radiance (n, 3)."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from . import PenumbraError

    array = polydata.GetPointData().GetArray("Radiance")
    if array is None or array.GetNumberOfComponents() != 3:
        raise PenumbraError("the result has no RGB point array 'Radiance' to write")
    cells = vtk_to_numpy(polydata.GetPolys().GetData())
    if len(cells) % 4 or (len(cells) and (cells[::4] != 3).any()):
        raise PenumbraError("the result's polygons are not all triangles")
    triangles = cells.reshape(-1, 4)[:, 1:]
    if not len(triangles):
        raise PenumbraError("the result has no triangles to write")
    used, triangles = np.unique(triangles, return_inverse=True)
    points = vtk_to_numpy(polydata.GetPoints().GetData()).astype(np.float64)[used]
    radiance = vtk_to_numpy(array).astype(np.float64)[used]
    return points, triangles.reshape(-1, 3), radiance


def _triangle_polydata(points, triangles):
    """A vtkPolyData of numpy points (n, 3) and triangles (m, 3)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    data = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=1))
    data.SetPoints(vtk_points)
    cells = vtkCellArray()
    connectivity = np.hstack([np.full((len(triangles), 1), 3), triangles]).ravel()
    cells.SetCells(len(triangles), numpy_to_vtkIdTypeArray(connectivity.astype(np.int64), deep=1))
    data.SetPolys(cells)
    return data


def _write_ply(points, triangles, radiance, exposure, path):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkIOPLY import vtkPLYWriter
    from . import PenumbraError
    from .rendering import radiance_to_colors

    data = _triangle_polydata(points, triangles)
    colors = numpy_to_vtk(radiance_to_colors(radiance, exposure), deep=1)
    colors.SetName("Colors")
    data.GetPointData().SetScalars(colors)
    writer = vtkPLYWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(data)
    writer.SetFileTypeToBinary()
    writer.SetArrayName("Colors")
    writer.SetColorModeToDefault()
    # The exposure, for whoever reads the file: PLY has comments.
    writer.AddComment("penumbra result: colours are sRGB of Radiance / %r clipped to [0, 1]"
                      % exposure)
    if writer.Write() != 1:
        raise PenumbraError("could not write %s" % path)


class _Buffer:
    """One glTF binary buffer assembled from views, each aligned to 4 bytes."""

    def __init__(self):
        self.data = bytearray()
        self.views = []

    def add(self, raw, target=None):
        self.data.extend(b"\0" * (-len(self.data) % 4))
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(raw)}
        if target is not None:
            view["target"] = target
        self.data.extend(raw)
        self.views.append(view)
        return len(self.views) - 1


def _accessor(document, buffer, array, component_type, kind, target, bounds=False):
    accessor = {"bufferView": buffer.add(array.tobytes(), target), "byteOffset": 0,
                "componentType": component_type, "count": int(len(array)), "type": kind}
    if bounds:
        accessor["min"] = [float(v) for v in array.min(axis=0)]
        accessor["max"] = [float(v) for v in array.max(axis=0)]
    document.setdefault("accessors", []).append(accessor)
    return len(document["accessors"]) - 1


def _save_gltf(document, buffer, path):
    """Write `document` with `buffer` as .glb or as a .gltf with the data inline."""
    data = bytes(buffer.data)
    document["buffers"] = [{"byteLength": len(data)}]
    document["bufferViews"] = buffer.views
    if str(path).lower().endswith(".glb"):
        text = json.dumps(document, separators=(",", ":")).encode("utf-8")
        text += b" " * (-len(text) % 4)
        data += b"\0" * (-len(data) % 4)
        length = 12 + 8 + len(text) + 8 + len(data)
        with open(path, "wb") as stream:
            stream.write(struct.pack("<4sII", b"glTF", 2, length))
            stream.write(struct.pack("<I4s", len(text), b"JSON") + text)
            stream.write(struct.pack("<I4s", len(data), b"BIN\0") + data)
        return
    document["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                     + base64.b64encode(data).decode("ascii"))
    with open(path, "w") as stream:
        json.dump(document, stream)


def _vtk_gltf_geometry(points, triangles):
    """The document and buffer vtkGLTFWriter writes for the triangles
    (positions, indices, a material, nodes), its data in one buffer of ours."""
    import numpy as np
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
    from vtkmodules.vtkIOGeometry import vtkGLTFWriter

    # glTF positions are single precision.
    data = _triangle_polydata(points.astype(np.float32), triangles)
    # VTK 9.1's writer takes a CityGML-like tree: blocks of blocks of pieces.
    piece, root = vtkMultiBlockDataSet(), vtkMultiBlockDataSet()
    piece.SetBlock(0, data)
    root.SetBlock(0, piece)
    writer = vtkGLTFWriter()
    writer.SetInputData(root)
    writer.InlineDataOn()  # data URIs: no side files with generated names
    document = json.loads(writer.WriteToString())
    # Gather the writer's buffers (one per view) into one.
    raw = [base64.b64decode(b["uri"].split(",", 1)[1]) for b in document.pop("buffers")]
    buffer = _Buffer()
    for view in document.pop("bufferViews"):  # in order: the accessors' indices hold
        offset = view.get("byteOffset", 0)
        buffer.add(raw[view["buffer"]][offset:offset + view["byteLength"]], view.get("target"))
    _drop_cameras(document)
    return document, buffer


def _drop_cameras(document):
    """Remove the camera nodes: VTK 9.1's writer places its camera by the view
    transform, not its inverse, so it looks away from the data; viewers frame
    the scene themselves."""
    nodes = document.get("nodes", [])
    kept = [k for k, node in enumerate(nodes) if "camera" not in node]
    index = {old: new for new, old in enumerate(kept)}
    document["nodes"] = [nodes[k] for k in kept]
    for node in document["nodes"]:
        if "children" in node:
            node["children"] = [index[c] for c in node["children"] if c in index]
    for scene in document.get("scenes", []):
        scene["nodes"] = [index[n] for n in scene.get("nodes", []) if n in index]
    document.pop("cameras", None)


def _write_result_gltf(points, triangles, radiance, exposure, path):
    import numpy as np

    document, buffer = _vtk_gltf_geometry(points, triangles)
    linear = np.clip(radiance / exposure, 0.0, 1.0)
    # Float, not 8 or 16-bit: glTF aligns every vertex to 4 bytes, and dark
    # linear values need more than 8 bits.
    color = _accessor(document, buffer, linear.astype(np.float32), _FLOAT, "VEC3",
                      _ARRAY_BUFFER)
    values = _accessor(document, buffer, radiance.astype(np.float32), _FLOAT, "VEC3",
                       _ARRAY_BUFFER)
    for mesh in document["meshes"]:
        for primitive in mesh["primitives"]:
            primitive["attributes"]["COLOR_0"] = color
            primitive["attributes"]["_RADIANCE"] = values
    for material in document.get("materials", []):
        material["pbrMetallicRoughness"]["baseColorFactor"] = [1.0, 1.0, 1.0, 1.0]
        material.setdefault("extensions", {})["KHR_materials_unlit"] = {}
    document["extensionsUsed"] = sorted(set(document.get("extensionsUsed", []))
                                        | {"KHR_materials_unlit"})
    document["asset"]["generator"] = "penumbra (geometry by VTK's vtkGLTFWriter)"
    document["asset"]["extras"] = {"penumbra": {
        "exposure": exposure,
        "COLOR_0": "clip(Radiance / exposure, 0, 1), linear",
        "_RADIANCE": "Radiance, W sr^-1 m^-2, linear RGB"}}
    _save_gltf(document, buffer, path)


def _material_key(reflectance, emission):
    return tuple(float(v) for v in reflectance) + tuple(float(v) for v in emission)


def _gltf_material(key, index):
    reflectance, emission = key[:3], key[3:]
    material = {"name": "surface material %d" % index,
                "pbrMetallicRoughness": {"baseColorFactor": list(reflectance) + [1.0],
                                         "metallicFactor": 0.0, "roughnessFactor": 1.0}}
    peak = max(emission)
    if peak > 1.0:
        material["emissiveFactor"] = [v / peak for v in emission]
        material["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": peak}}
    elif peak > 0.0:
        material["emissiveFactor"] = list(emission)
    return material


def _write_scene_gltf(polydata, path):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkTriangleFilter
    from . import PenumbraError

    arrays = [polydata.GetCellData().GetArray(name) for name in ("Reflectance", "Emission")]
    if any(a is None or a.GetNumberOfComponents() != 3 for a in arrays):
        raise PenumbraError("the scene has no RGB cell arrays 'Reflectance' and 'Emission'")
    # Concave polygons need the ear clipping of the triangle filter, which
    # keeps the cells' order and passes their data.
    triangulate = vtkTriangleFilter()
    triangulate.SetInputData(polydata)
    triangulate.PassLinesOff()
    triangulate.PassVertsOff()
    triangulate.Update()
    triangulated = triangulate.GetOutput()
    points = vtk_to_numpy(triangulated.GetPoints().GetData()).astype(np.float32)
    corners = vtk_to_numpy(triangulated.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    reflectance, emission = (vtk_to_numpy(triangulated.GetCellData().GetArray(name))
                             for name in ("Reflectance", "Emission"))
    document = {"asset": {"version": "2.0", "generator": "penumbra"},
                "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": []}], "materials": []}
    buffer = _Buffer()
    materials = {}
    start = 0
    keys = [_material_key(r, e) for r, e in zip(reflectance, emission)]
    for end in range(1, len(keys) + 1):
        if end < len(keys) and keys[end] == keys[start]:
            continue
        key = keys[start]
        if key not in materials:
            materials[key] = len(materials)
            document["materials"].append(_gltf_material(key, materials[key]))
        # Each run's own vertices, so that the file holds only what it draws.
        used, local = np.unique(corners[start:end], return_inverse=True)
        position = _accessor(document, buffer, points[used], _FLOAT, "VEC3", _ARRAY_BUFFER,
                             bounds=True)
        indices = _accessor(document, buffer, local.astype(np.uint32), _UNSIGNED_INT,
                            "SCALAR", _ELEMENT_ARRAY_BUFFER)
        document["meshes"][0]["primitives"].append(
            {"attributes": {"POSITION": position}, "indices": indices,
             "material": materials[key], "mode": 4})
        start = end
    if any("extensions" in m for m in document["materials"]):
        document["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    _save_gltf(document, buffer, path)
