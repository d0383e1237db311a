# SPDX-License-Identifier: GPL-3.0-or-later
"""What a solved result records about its solve, as lines of text.

`penumbra info OUT.vtp` prints `report_lines`; `penumbra solve` ends with
`summary_lines`. Everything comes from the result itself (its field data and
point arrays, see the data contract in Documentation/design.md), so a result
file can be audited long after the solve.
"""


def read_result(path):
    """The polydata of a result .vtp (raises PenumbraError if unreadable)."""
    import penumbra
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

    penumbra._check_vtp_counts(path)
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    return penumbra.run_filter(reader, context=path)


def _field(data, name):
    """The values of field array `name` as a list (None when absent)."""
    array = data.GetFieldData().GetAbstractArray(name)
    if array is None:
        return None
    count = array.GetNumberOfTuples() * array.GetNumberOfComponents()
    return [array.GetVariantValue(k).ToString() if array.IsA("vtkStringArray")
            else array.GetVariantValue(k).ToDouble() for k in range(count)]


def energy_balance(data):
    """{name: fraction of the emitted power} for Absorbed, Escaped, Residual and
    Unshot power (channels summed), or None without a shooter's record."""
    emitted = _field(data, "EmittedPower")
    if not emitted or sum(emitted) <= 0:
        return None
    total = sum(emitted)
    balance = {}
    for name in ("AbsorbedPower", "EscapedPower", "ResidualPower", "UnshotPower"):
        values = _field(data, name)
        if values is not None:
            balance[name[:-len("Power")]] = sum(values) / total
    return balance


def estimated_error(data):
    """(overall, worst, worst_surface): the reconstruction's own error estimate
    (`RadianceErrorEstimate`) as an area-weighted RMS relative to the
    area-weighted mean radiance, over the lit surfaces that do not emit, and the
    largest such value of one surface with its SurfaceId; None when the result
    has no estimate."""
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from .rendering import _triangles

    estimate = data.GetPointData().GetArray("RadianceErrorEstimate")
    radiance = data.GetPointData().GetArray("Radiance")
    if estimate is None or radiance is None or data.GetCellData().GetArray("SurfaceId") is None \
            or not data.GetNumberOfPolys():
        return None
    points, triangles, surface = _triangles(data)
    a, b, c = (points[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    value = vtk_to_numpy(radiance).sum(axis=1)[triangles].mean(axis=1)
    error = (vtk_to_numpy(estimate).sum(axis=1)[triangles] ** 2).mean(axis=1)
    emission = data.GetFieldData().GetArray("SurfaceEmission")
    emitting = (np.nonzero(vtk_to_numpy(emission).max(axis=1) > 0)[0] if emission is not None
                else np.zeros(0, dtype=int))
    keep = ~np.isin(surface, emitting)
    if not keep.any():
        return None
    area, value, error, surface = area[keep], value[keep], error[keep], surface[keep]
    mean = np.sum(area * value) / max(np.sum(area), 1e-300)
    # Per surface, by sums over its triangles. Unlit surfaces (e.g. faces
    # turned into a closed solid) carry no light to be wrong about; they are
    # left out of both figures.
    surface_area = np.bincount(surface, area)
    present = surface_area > 0
    surface_mean = np.bincount(surface, area * value)[present] / surface_area[present]
    surface_error = np.bincount(surface, area * error)[present] / surface_area[present]
    ids = np.nonzero(present)[0]
    lit_surfaces = surface_mean > 1e-6 * mean
    if not lit_surfaces.any():
        return None
    relative = np.sqrt(surface_error[lit_surfaces]) / surface_mean[lit_surfaces]
    best = int(np.argmax(relative))
    worst, worst_surface = float(relative[best]), int(ids[lit_surfaces][best])
    if worst <= 0.0:
        worst, worst_surface = 0.0, -1
    lit = np.isin(surface, ids[lit_surfaces])
    lit_mean = np.sum(area[lit] * value[lit]) / np.sum(area[lit])
    overall = np.sqrt(np.sum(area[lit] * error[lit]) / np.sum(area[lit])) / lit_mean
    return float(overall), worst, worst_surface


def summary_lines(data):
    """The few lines `penumbra solve` prints after writing its result."""
    lines = []
    shots = _field(data, "Shots")
    balance = energy_balance(data)
    if shots is not None and balance is not None:
        lines.append("%d shots; of the emitted power: absorbed %.4g, escaped %.2g, residual "
                     "%.2g, unshot %.2g" % (shots[0], balance.get("Absorbed", 0.0),
                                            balance.get("Escaped", 0.0),
                                            balance.get("Residual", 0.0),
                                            balance.get("Unshot", 0.0)))
    coarse = coarse_level_line(data)
    if coarse:
        lines.append(coarse)
    error = estimated_error(data)
    if error is not None:
        lines.append("estimated error: %.2g%% RMS of the mean radiance (largest on one surface "
                     "%.2g%%, surface %d)" % (100 * error[0], 100 * error[1], error[2]))
    return lines


def coarse_level_line(data):
    """When the interreflections were shot on the coarse level (more samples
    than MaximumIndirectSamples), a line saying so, or None."""
    spacing = _field(data, "IndirectSpacing")
    points = _field(data, "IndirectSamples")
    if not spacing or not points or not spacing[0] > 0:
        return None
    alone = _field(data, "IndirectSeparatePoints")
    return ("interreflections on the coarse level (MaximumIndirectSamples): %d points, lattice "
            "spacing %.3g, %d of them near occluders on their own"
            % (points[0], spacing[0], alone[0] if alone else 0))


def report_lines(data):
    """Every recorded fact of a result, one per line, for `penumbra info`."""
    lines = []
    reflectance = data.GetFieldData().GetArray("SurfaceReflectance")
    if reflectance is not None:
        emission = _field(data, "SurfaceEmission") or []
        emitters = sum(1 for k in range(0, len(emission), 3) if max(emission[k:k + 3]) > 0)
        lines.append("surfaces: %d (%d emitting)" % (reflectance.GetNumberOfTuples(), emitters))
    lines.append("output: %d points, %d triangles, %d boundary lines"
                 % (data.GetNumberOfPoints(), data.GetNumberOfPolys(), data.GetNumberOfLines()))
    for name, label in (("Evaluations", "exact evaluations (direct light)"),
                        ("IndirectSamples", "indirect samples")):
        values = _field(data, name)
        if values is not None:
            lines.append("%s: %d" % (label, values[0]))
    shots = _field(data, "Shots")
    if shots is not None:
        exact, fast = _field(data, "ExactShots"), _field(data, "FastShots")
        lines.append("shots: %d (%d exact, %d fast)" % (shots[0], exact[0] if exact else 0,
                                                        fast[0] if fast else 0))
    emitted = _field(data, "EmittedPower")
    balance = energy_balance(data)
    if balance is not None:
        lines.append("emitted power: %s W (RGB)" % ", ".join("%.6g" % v for v in emitted))
        lines.append("energy balance (fractions of the emitted power): "
                     + ", ".join("%s %.4g" % (name.lower(), value)
                                 for name, value in balance.items()))
    coarse = coarse_level_line(data)
    if coarse:
        lines.append(coarse)
    error = estimated_error(data)
    if error is not None:
        lines.append("estimated error: %.3g%% RMS of the mean radiance; largest on one surface "
                     "%.3g%% (surface %d)" % (100 * error[0], 100 * error[1], error[2]))
    stages = [(label, _field(data, name + "Seconds")) for name, label in
              (("Mesher", "mesher"), ("Evaluator", "evaluator"),
               ("SecondaryShooters", "secondary shooters"), ("Shooter", "shooter"),
               ("Reconstructor", "reconstructor"))]
    stages = [(name, value[0]) for name, value in stages if value is not None]
    total = _field(data, "SolveSeconds")
    if stages:
        lines.append("time per stage: " + ", ".join("%s %.2f s" % (name, seconds)
                                                    for name, seconds in stages)
                     + (" (solve %.2f s)" % total[0] if total else ""))
    settings = _field(data, "SolverSettings")
    if settings:
        lines.append("settings: %s" % settings[0])
    if len(lines) == 1 and data.GetPointData().GetArray("Radiance") is None:
        lines.append("not a solved result: no Radiance (a scene?)")
    return lines
