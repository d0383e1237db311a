# SPDX-License-Identifier: GPL-3.0-or-later
"""glTF 2.0 in and out, PLY out: files written here with json and struct, as
Blender writes them, read by vtkPenumbraGLTFReader; scenes and results written
by penumbra.export, read back by VTK's own readers and by this file's parser."""
import base64
import json
import math
import os
import struct

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

import penumbra
from penumbra import export
from conftest import SCENE_DIR, run_penumbra


# --- a small glTF writer of the test's own ------------------------------------

class GLTF:
    """A glTF document and its one binary buffer, built by hand."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0", "generator": "test"}, "scene": 0,
                    "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": []}
        self.data = bytearray()

    def accessor(self, values, fmt, kind, component_type, target):
        values = np.asarray(values)
        self.data.extend(b"\0" * (-len(self.data) % 4))
        flat = values.reshape(-1).tolist()
        raw = struct.pack("<%d%s" % (len(flat), fmt), *flat)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.data),
                                        "byteLength": len(raw), "target": target})
        self.data.extend(raw)
        accessor = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": component_type,
                    "count": len(values), "type": kind}
        if kind == "VEC3" and component_type == 5126 and np.isfinite(values).all():
            accessor["min"] = values.min(axis=0).tolist()
            accessor["max"] = values.max(axis=0).tolist()
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def primitive(self, positions, triangles, material=None):
        """Indexed triangles with NORMAL and TEXCOORD_0, as Blender writes them."""
        positions = np.asarray(positions, dtype=np.float32)
        normals = np.tile([0.0, 0.0, 1.0], (len(positions), 1))
        uv = positions[:, :2]
        primitive = {"attributes": {
            "POSITION": self.accessor(positions, "f", "VEC3", 5126, 34962),
            "NORMAL": self.accessor(normals, "f", "VEC3", 5126, 34962),
            "TEXCOORD_0": self.accessor(uv, "f", "VEC2", 5126, 34962)},
            "indices": self.accessor(np.asarray(triangles).reshape(-1), "H", "SCALAR", 5123,
                                     34963),
            "mode": 4}
        if material is not None:
            primitive["material"] = material
        return primitive

    def save(self, path):
        # glTF forbids empty arrays.
        doc = {k: v for k, v in json.loads(json.dumps(self.doc)).items() if v != []}
        data = bytes(self.data) + b"\0" * (-len(self.data) % 4)
        doc["buffers"] = [{"byteLength": len(data)}]
        if str(path).endswith(".glb"):
            text = json.dumps(doc).encode()
            text += b" " * (-len(text) % 4)
            with open(path, "wb") as stream:
                stream.write(struct.pack("<4sII", b"glTF", 2, 28 + len(text) + len(data)))
                stream.write(struct.pack("<I4s", len(text), b"JSON") + text)
                stream.write(struct.pack("<I4s", len(data), b"BIN\0") + data)
        else:
            doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                        + base64.b64encode(data).decode())
            with open(path, "w") as stream:
                json.dump(doc, stream)


def read_gltf(path):
    """(document, binary buffer) of a .gltf with one data URI or a .glb."""
    raw = open(path, "rb").read()
    if raw[:4] == b"glTF":
        length, kind = struct.unpack_from("<I4s", raw, 12)
        assert kind == b"JSON"
        doc = json.loads(raw[20:20 + length])
        bin_length, bin_kind = struct.unpack_from("<I4s", raw, 20 + length)
        assert bin_kind == b"BIN\0"
        return doc, raw[28 + length:28 + length + bin_length]
    doc = json.loads(raw)
    (buffer,) = doc["buffers"]
    return doc, base64.b64decode(buffer["uri"].split(",", 1)[1])


def accessor_values(doc, data, index):
    accessor = doc["accessors"][index]
    view = doc["bufferViews"][accessor["bufferView"]]
    fmt = {5126: "f", 5123: "H", 5125: "I", 5121: "B"}[accessor["componentType"]]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[accessor["type"]]
    offset = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    values = np.frombuffer(data, dtype="<" + fmt, count=accessor["count"] * width, offset=offset)
    return values.reshape(accessor["count"], width) if width > 1 else values


# --- independent transforms ---------------------------------------------------

def trs_matrix(translation=(0, 0, 0), rotation=(0, 0, 0, 1), scale=(1, 1, 1)):
    x, y, z, w = rotation
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * np.asarray(scale, dtype=float)
    m[:3, 3] = translation
    return m


def axis_angle(axis, degrees):
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    half = math.radians(degrees) / 2
    return tuple(axis * math.sin(half)) + (math.cos(half),)


def cells_of(polydata):
    """Each polygon cell's vertices, as a list of (k, 3) arrays."""
    points = vtk_to_numpy(polydata.GetPoints().GetData())
    connectivity = vtk_to_numpy(polydata.GetPolys().GetConnectivityArray())
    offsets = vtk_to_numpy(polydata.GetPolys().GetOffsetsArray())
    return [points[connectivity[a:b]] for a, b in zip(offsets[:-1], offsets[1:])]


def read_scene(path):
    reader = penumbra.vtkPenumbraGLTFReader()
    reader.SetFileName(str(path))
    return penumbra.run_filter(reader)


def cell_array(polydata, name):
    return vtk_to_numpy(polydata.GetCellData().GetArray(name))


# --- reading a Blender-like file ----------------------------------------------

QUAD = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=np.float32)
QUAD_TRIANGLES = [[0, 1, 2], [0, 2, 3]]
TRIANGLE = np.array([[0, 0, 0], [0.5, 0, 0], [0, 0.25, 0]], dtype=np.float32)


def blender_like_file():
    """Returns (GLTF, expected triangles world positions, reflectance, emission)."""
    g = GLTF()
    g.doc["materials"] = [
        {"name": "Red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.05, 1.0],
                                                 "metallicFactor": 0.0, "roughnessFactor": 0.5}},
        {"name": "Grey", "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.3, 0.3, 1.0]}},
        {"name": "Lamp", "emissiveFactor": [1.0, 0.8, 0.6],
         "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 7.5}}},
    ]
    g.doc["extensionsUsed"] = ["KHR_materials_emissive_strength"]
    g.doc["meshes"] = [
        {"name": "Panels", "primitives": [g.primitive(QUAD, QUAD_TRIANGLES, 0),
                                          g.primitive(QUAD + [0, 0, 2], QUAD_TRIANGLES, 1)]},
        {"name": "Light", "primitives": [g.primitive(TRIANGLE, [[0, 1, 2]], 2),
                                         g.primitive(TRIANGLE + [1, 0, 0], [[0, 1, 2]])]},
    ]
    parent = dict(translation=(1.0, 2.0, -0.5), rotation=axis_angle((0, 1, 0), 30),
                  scale=(2.0, 2.0, 2.0))
    child = dict(translation=(0.0, 0.5, 0.0), rotation=axis_angle((1, 0, 0), -90),
                 scale=(1.0, 0.5, 1.5))
    light = trs_matrix((0.25, 3.0, 0.0), axis_angle((1, 1, 0), 45))
    g.doc["nodes"] = [
        {"name": "Parent", "children": [1, 2], **{k: list(v) for k, v in parent.items()}},
        {"name": "PanelsObject", "mesh": 0, **{k: list(v) for k, v in child.items()}},
        {"name": "LightObject", "mesh": 1, "matrix": light.T.reshape(-1).tolist()},
    ]
    g.doc["scenes"] = [{"name": "Scene", "nodes": [0]}]
    p = trs_matrix(**parent)
    expected = []
    for transform, primitives in ((p @ trs_matrix(**child), [(QUAD, QUAD_TRIANGLES),
                                                             (QUAD + [0, 0, 2], QUAD_TRIANGLES)]),
                                  (p @ light, [(TRIANGLE, [[0, 1, 2]]),
                                               (TRIANGLE + [1, 0, 0], [[0, 1, 2]])])):
        for positions, triangles in primitives:
            world = (transform @ np.c_[positions, np.ones(len(positions))].T).T[:, :3]
            expected += [world[t] for t in triangles]
    reflectance = [[0.8, 0.1, 0.05]] * 2 + [[0.3, 0.3, 0.3]] * 2 + [[0, 0, 0], [0.5] * 3]
    emission = [[0, 0, 0]] * 4 + [[7.5, 6.0, 4.5], [0, 0, 0]]
    return g, expected, np.array(reflectance), np.array(emission)


@pytest.mark.parametrize("extension", [".gltf", ".glb"])
def test_reads_blender_like_file_in_world_coordinates(tmp_path, extension):
    g, expected, reflectance, emission = blender_like_file()
    path = tmp_path / ("scene" + extension)
    g.save(path)
    scene = read_scene(path)
    cells = cells_of(scene)
    assert len(cells) == len(expected)
    for cell, triangle in zip(cells, expected):
        np.testing.assert_allclose(cell, triangle, atol=1e-6)
    np.testing.assert_allclose(cell_array(scene, "Reflectance"), reflectance, rtol=1e-15)
    np.testing.assert_allclose(cell_array(scene, "Emission"), emission, rtol=1e-15)


def test_a_mirroring_transform_keeps_the_front_face(tmp_path):
    g = GLTF()
    g.doc["meshes"] = [{"primitives": [g.primitive(TRIANGLE, [[0, 1, 2]])]}]
    g.doc["nodes"] = [{"mesh": 0, "scale": [-1.0, 1.0, 1.0]}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(tmp_path / "mirror.gltf")
    (cell,) = cells_of(read_scene(tmp_path / "mirror.gltf"))
    # glTF: under a negative determinant the front face is clockwise; it still
    # faces +z, so the polygon's right-hand normal must be +z.
    normal = np.cross(cell[1] - cell[0], cell[2] - cell[0])
    assert normal[2] > 0 and np.allclose(sorted(cell[:, 0]), [-0.5, 0, 0])


def same_polygon(cell, vertices):
    """Equal up to a cyclic rotation (same polygon, same orientation)."""
    return any(np.allclose(np.roll(cell, k, axis=0), vertices) for k in range(len(cell)))


@pytest.mark.parametrize("mode", [5, 6])
def test_strips_and_fans_become_triangles(tmp_path, mode):
    fan = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0.5, 1.5, 0], [0, 1, 0]], np.float32)
    g = GLTF()
    primitive = g.primitive(fan, [0, 1, 2, 3, 4])
    primitive["mode"] = mode
    g.doc["meshes"] = [{"primitives": [primitive]}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(tmp_path / "strip.gltf")
    cells = cells_of(read_scene(tmp_path / "strip.gltf"))
    # The glTF specification's triangles of a strip and of a fan.
    if mode == 5:
        expected = [[i, i + 1 + i % 2, i + 2 - i % 2] for i in range(3)]
    else:
        expected = [[i + 1, i + 2, 0] for i in range(3)]
    assert len(cells) == 3
    for cell, triangle in zip(cells, expected):
        assert same_polygon(cell, fan[triangle]), (cell, fan[triangle])


def read_with_warnings(path):
    """The reader's output and what it wrote to VTK's output window."""
    window = vtkStringOutputWindow()
    previous = vtkOutputWindow.GetInstance()
    vtkOutputWindow.SetInstance(window)
    try:
        reader = penumbra.vtkPenumbraGLTFReader()
        reader.SetFileName(str(path))
        reader.Update()
    finally:
        vtkOutputWindow.SetInstance(previous)
    return reader.GetOutput(), window.GetOutput()


def test_line_primitives_are_skipped_with_a_warning(tmp_path):
    g = GLTF()
    lines = g.primitive(QUAD, [0, 1, 1, 2])
    lines["mode"] = 1
    g.doc["meshes"] = [{"primitives": [lines, g.primitive(TRIANGLE, [[0, 1, 2]])]}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(tmp_path / "lines.gltf")
    scene, warnings = read_with_warnings(tmp_path / "lines.gltf")
    assert scene.GetNumberOfCells() == 1 and "skipped 1 primitive" in warnings


def test_texture_mean_and_warning(tmp_path):
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.util.numpy_support import numpy_to_vtk

    pixels = np.array([[255, 0, 0], [0, 128, 255], [64, 64, 64], [255, 255, 255]], np.uint8)
    image = vtkImageData()
    image.SetDimensions(2, 2, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(pixels, deep=1))
    png = vtkPNGWriter()
    png.SetInputData(image)
    png.WriteToMemoryOn()
    png.Write()
    encoded = base64.b64encode(bytes(vtk_to_numpy(png.GetResult()))).decode()
    g = GLTF()
    g.doc["images"] = [{"uri": "data:image/png;base64," + encoded}]
    g.doc["textures"] = [{"source": 0}]
    g.doc["materials"] = [{"name": "Painted", "pbrMetallicRoughness": {
        "baseColorFactor": [0.9, 0.8, 0.7, 1.0], "baseColorTexture": {"index": 0}}}]
    g.doc["meshes"] = [{"primitives": [g.primitive(TRIANGLE, [[0, 1, 2]], 0)]}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(tmp_path / "painted.gltf")
    c = pixels / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    expected = np.array([0.9, 0.8, 0.7]) * linear.mean(axis=0)

    scene, warnings = read_with_warnings(tmp_path / "painted.gltf")
    np.testing.assert_allclose(cell_array(scene, "Reflectance")[0], expected, rtol=1e-12)
    assert "Painted" in warnings and "texture" in warnings
    # A warning is not an error: the scene loads.
    assert penumbra.load_scene(str(tmp_path / "painted.gltf")).GetNumberOfCells() == 1


def test_bad_files_name_the_file(tmp_path):
    (tmp_path / "text.gltf").write_text("solid cube\nfacet normal 0 0 1\n")
    (tmp_path / "json.glb").write_text('{"asset": {"version": "2.0"}}')
    g = GLTF()
    g.doc["meshes"] = [{"primitives": [g.primitive(TRIANGLE * np.float32("nan"), [[0, 1, 2]])]}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(tmp_path / "nan.gltf")
    long = GLTF()  # an accessor longer than its data: VTK's loader would read past it
    long.doc["meshes"] = [{"primitives": [long.primitive(TRIANGLE, [[0, 1, 2]])]}]
    long.doc["accessors"][0]["count"] = 10 ** 6
    long.doc["nodes"] = [{"mesh": 0}]
    long.doc["scenes"] = [{"nodes": [0]}]
    long.save(tmp_path / "long.gltf")
    draco = GLTF()  # compressed meshes are not read: refuse rather than read nothing
    draco.doc["extensionsUsed"] = draco.doc["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    draco.save(tmp_path / "draco.glb")
    cycle = GLTF()
    cycle.doc["nodes"] = [{"children": [1]}, {"children": [0]}]
    cycle.doc["scenes"] = [{"nodes": [0]}]
    cycle.save(tmp_path / "cycle.gltf")
    for name, fragment in (("text.gltf", "not glTF"), ("json.glb", "binary glTF"),
                           ("nan.gltf", "non-finite"), ("cycle.gltf", "own ancestor"),
                           ("long.gltf", "runs past the end"),
                           ("draco.glb", "KHR_draco_mesh_compression"),
                           ("absent.glb", "not found")):
        path = str(tmp_path / name)
        with pytest.raises(penumbra.PenumbraError) as error:
            penumbra.load_scene(path)
        assert fragment in str(error.value), str(error.value)
        if name != "absent.glb":
            assert name in str(error.value), str(error.value)


# --- the round trip: one scene as OBJ and as glTF solves the same ------------

# A closed 1 m box of triangles facing inwards, a square light under its
# ceiling; every coordinate is exact in single precision.
BOX = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
WALLS = {  # quads counter-clockwise seen from inside
    "floor": ([0, 4, 5, 1], [0.6, 0.6, 0.6]), "ceiling": ([3, 2, 6, 7], [0.7, 0.7, 0.7]),
    "back": ([0, 1, 2, 3], [0.5, 0.5, 0.5]), "front": ([4, 7, 6, 5], [0.5, 0.5, 0.5]),
    "left": ([0, 3, 7, 4], [0.6, 0.1, 0.1]), "right": ([1, 5, 6, 2], [0.1, 0.6, 0.1]),
}
LIGHT = np.array([[0.375, 0.96875, 0.375], [0.625, 0.96875, 0.375],
                  [0.625, 0.96875, 0.625], [0.375, 0.96875, 0.625]])
LIGHT_EMISSION = [3.0, 2.5, 2.0]


def box_triangles():
    """[(3 vertices, reflectance, emission)] in one fixed order."""
    triangles = []
    for quad, reflectance in WALLS.values():
        a, b, c, d = BOX[quad]
        triangles += [(np.array([a, b, c]), reflectance, [0, 0, 0]),
                      (np.array([a, c, d]), reflectance, [0, 0, 0])]
    a, b, c, d = LIGHT  # facing down: clockwise seen from above
    triangles += [(np.array([a, b, c]), [0.0, 0.0, 0.0], LIGHT_EMISSION),
                  (np.array([a, c, d]), [0.0, 0.0, 0.0], LIGHT_EMISSION)]
    return triangles


def write_box_obj(path):
    triangles = box_triangles()
    materials = sorted({(tuple(r), tuple(e)) for _, r, e in triangles})
    with open(os.path.splitext(path)[0] + ".mtl", "w") as mtl:
        for k, (r, e) in enumerate(materials):
            mtl.write("newmtl m%d\nKd %r %r %r\nKe %r %r %r\n" % ((k,) + r + e))
    with open(path, "w") as obj:
        obj.write("mtllib %s\n" % os.path.basename(os.path.splitext(path)[0] + ".mtl"))
        for vertices, _, _ in triangles:
            for v in vertices:
                obj.write("v %r %r %r\n" % tuple(v))
        for k, (_, r, e) in enumerate(triangles):
            obj.write("usemtl m%d\nf %d %d %d\n"
                      % (materials.index((tuple(r), tuple(e))), 3 * k + 1, 3 * k + 2, 3 * k + 3))


def write_box_gltf(path):
    g = GLTF()
    primitives = []
    for vertices, reflectance, emission in box_triangles():
        peak = max(emission)
        material = {"pbrMetallicRoughness": {"baseColorFactor": list(reflectance) + [1.0]}}
        if peak > 0:
            material["emissiveFactor"] = [e / peak for e in emission]
            material["extensions"] = {
                "KHR_materials_emissive_strength": {"emissiveStrength": peak}}
        g.doc["materials"].append(material)
        primitives.append(g.primitive(vertices, [[0, 1, 2]], len(g.doc["materials"]) - 1))
    g.doc["meshes"] = [{"primitives": primitives}]
    g.doc["nodes"] = [{"mesh": 0}]
    g.doc["scenes"] = [{"nodes": [0]}]
    g.save(path)


# Coarse but with indirect light: the round trip covers the shooter too.
FAST = dict(threads=1, sampling_tolerance=2e-3, unshot_fraction=0.2)


def test_obj_and_gltf_of_one_scene_solve_the_same(tmp_path):
    write_box_obj(str(tmp_path / "box.obj"))
    write_box_gltf(str(tmp_path / "box.gltf"))
    obj_scene = penumbra.load_scene(str(tmp_path / "box.obj"))
    gltf_scene = penumbra.load_scene(str(tmp_path / "box.gltf"))
    for a, b in zip(cells_of(obj_scene), cells_of(gltf_scene)):
        np.testing.assert_array_equal(a, b)
    for name in ("Reflectance", "Emission"):
        np.testing.assert_allclose(cell_array(gltf_scene, name), cell_array(obj_scene, name),
                                   rtol=1e-15)
    results = [penumbra.solve(str(tmp_path / name), **FAST) for name in ("box.obj", "box.gltf")]
    radiance = [vtk_to_numpy(r.GetPointData().GetArray("Radiance")) for r in results]
    assert radiance[0].shape == radiance[1].shape and radiance[0].max() > 0
    np.testing.assert_allclose(radiance[1], radiance[0], rtol=1e-9, atol=1e-9 * radiance[0].max())


def test_a_scene_written_as_gltf_reads_back_the_same(tmp_path):
    write_box_obj(str(tmp_path / "box.obj"))
    scene = penumbra.load_scene(str(tmp_path / "box.obj"))
    for extension in (".gltf", ".glb"):
        path = str(tmp_path / ("written" + extension))
        export.write_scene(scene, path)
        again = penumbra.load_scene(path)
        assert again.GetNumberOfCells() == scene.GetNumberOfCells()
        for a, b in zip(cells_of(scene), cells_of(again)):
            np.testing.assert_allclose(b, a, atol=1e-7)
        for name in ("Reflectance", "Emission"):
            np.testing.assert_allclose(cell_array(again, name), cell_array(scene, name),
                                       rtol=1e-15)
        doc, _ = read_gltf(path)
        # Emission above 1 needs the strength extension; factors stay in [0, 1].
        assert "KHR_materials_emissive_strength" in doc["extensionsUsed"]
        assert all(0 <= f <= 1 for m in doc["materials"] for f in m.get("emissiveFactor", []))


# --- results as glTF and PLY --------------------------------------------------

@pytest.fixture(scope="module")
def box_result(tmp_path_factory):
    folder = tmp_path_factory.mktemp("result")
    write_box_obj(str(folder / "box.obj"))
    return penumbra.solve(str(folder / "box.obj"), indirect=False, **FAST)


def result_triangles(result):
    """The result's triangles as corner point ids (m, 3), and its Radiance."""
    cells = vtk_to_numpy(result.GetPolys().GetData()).reshape(-1, 4)
    assert (cells[:, 0] == 3).all()
    return cells[:, 1:], vtk_to_numpy(result.GetPointData().GetArray("Radiance"))


def srgb8(linear):
    x = np.clip(linear, 0, 1)
    return np.round(255 * np.where(x <= 0.0031308, 12.92 * x,
                                   1.055 * x ** (1 / 2.4) - 0.055)).astype(int)


@pytest.mark.parametrize("extension", [".gltf", ".glb"])
def test_result_gltf_has_colours_and_radiance(tmp_path, box_result, extension):
    from vtkmodules.vtkIOGeometry import vtkGLTFReader

    triangles, radiance = result_triangles(box_result)
    exposure = 0.5 * radiance.max()
    path = str(tmp_path / ("result" + extension))
    assert export.write_result(box_result, path, exposure=exposure) == exposure
    expected = np.clip(radiance[triangles] / exposure, 0, 1)  # (m, 3 corners, RGB)

    reader = vtkGLTFReader()
    reader.SetFileName(path)
    reader.Update()
    iterator = reader.GetOutput().NewIterator()
    iterator.InitTraversal()
    mesh = iterator.GetCurrentDataObject()
    colours = vtk_to_numpy(mesh.GetPointData().GetArray("COLOR_0"))
    read_triangles = vtk_to_numpy(mesh.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    assert len(read_triangles) == len(triangles)  # triangles only, no boundary lines
    points = vtk_to_numpy(mesh.GetPoints().GetData())
    result_points = vtk_to_numpy(box_result.GetPoints().GetData())
    np.testing.assert_allclose(points[read_triangles], result_points[triangles], atol=1e-6)
    np.testing.assert_allclose(colours[read_triangles][..., :3], expected, rtol=1e-6, atol=1e-7)
    # What a viewer shows: the 8-bit sRGB tone map (single precision may round
    # a value on a step to the next one).
    assert np.abs(srgb8(colours[read_triangles][..., :3]) - srgb8(expected)).max() <= 1

    doc, data = read_gltf(path)
    (primitive,) = doc["meshes"][0]["primitives"]
    indices = accessor_values(doc, data, primitive["indices"]).reshape(-1, 3)
    values = accessor_values(doc, data, primitive["attributes"]["_RADIANCE"])
    np.testing.assert_allclose(values[indices], radiance[triangles], rtol=1e-6)
    assert doc["asset"]["extras"]["penumbra"]["exposure"] == exposure
    assert "KHR_materials_unlit" in doc["extensionsUsed"]
    assert "cameras" not in doc and all("camera" not in node for node in doc["nodes"])
    try:
        import pygltflib
    except ImportError:
        return
    gltf = pygltflib.GLTF2().load(path)
    attributes = gltf.meshes[0].primitives[0].attributes
    assert attributes.COLOR_0 is not None and attributes._RADIANCE is not None
    assert gltf.asset.extras["penumbra"]["exposure"] == exposure


def test_result_default_exposure_is_the_area_99th_percentile(tmp_path, box_result):
    triangles, radiance = result_triangles(box_result)
    export.write_result(box_result, str(tmp_path / "r.glb"))
    exposure = read_gltf(str(tmp_path / "r.glb"))[0]["asset"]["extras"]["penumbra"]["exposure"]
    points = vtk_to_numpy(box_result.GetPoints().GetData())
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    weights = np.zeros(len(points))
    for k in range(3):
        np.add.at(weights, triangles[:, k], area / 3)
    peak = radiance.max(axis=1)
    assert weights[peak > exposure].sum() <= 0.01 * weights.sum()
    assert weights[peak >= exposure].sum() >= 0.01 * weights.sum()


def test_result_ply_has_srgb_colours(tmp_path, box_result):
    from vtkmodules.vtkIOPLY import vtkPLYReader

    triangles, radiance = result_triangles(box_result)
    exposure = 0.8 * radiance.max()
    export.write_result(box_result, str(tmp_path / "result.ply"), exposure=exposure)
    reader = vtkPLYReader()
    reader.SetFileName(str(tmp_path / "result.ply"))
    reader.Update()
    mesh = reader.GetOutput()
    read_triangles = vtk_to_numpy(mesh.GetPolys().GetData()).reshape(-1, 4)[:, 1:]
    assert len(read_triangles) == len(triangles)
    colours = vtk_to_numpy(mesh.GetPointData().GetArray("RGB")).astype(int)
    np.testing.assert_array_equal(colours[read_triangles], srgb8(radiance[triangles] / exposure))


def test_unknown_extension_is_an_error(tmp_path, box_result):
    with pytest.raises(penumbra.PenumbraError, match="unknown extension '.stl'"):
        export.write_result(box_result, str(tmp_path / "x.stl"))
    with pytest.raises(penumbra.PenumbraError, match="unknown extension '.ply'"):
        export.write_scene(box_result, str(tmp_path / "x.ply"))


# --- the command line ---------------------------------------------------------

def test_cli_solves_to_glb_and_rejects_unknown_extensions(tmp_path):
    box = os.path.join(SCENE_DIR, "box.obj")
    result = run_penumbra("solve", box, "-o", tmp_path / "box.glb", "--direct-only",
                          "--set", "SamplingTolerance=2e-3")
    assert result.returncode == 0, result.stderr
    doc, data = read_gltf(str(tmp_path / "box.glb"))
    assert "COLOR_0" in doc["meshes"][0]["primitives"][0]["attributes"]
    for command in (("solve", box, "-o", tmp_path / "box.obj"),
                    ("scene", box, "-o", tmp_path / "box.ply")):
        failed = run_penumbra(*command)
        assert failed.returncode != 0
        lines = failed.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("penumbra: error:"), failed.stderr
        assert "unknown extension" in lines[0]
    assert not (tmp_path / "box.obj").exists()


def test_cli_scene_as_gltf_reads_back(tmp_path):
    box = os.path.join(SCENE_DIR, "box.obj")
    assert run_penumbra("scene", box, "-o", tmp_path / "box.gltf").returncode == 0
    result = run_penumbra("scene", tmp_path / "box.gltf", "-o", tmp_path / "again.vtp")
    assert result.returncode == 0, result.stderr
    # The OBJ's 7 polygons (quads) are glTF's 14 triangles.
    assert "(14 polygons)" in result.stdout
