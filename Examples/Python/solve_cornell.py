# SPDX-License-Identifier: GPL-3.0-or-later
"""Solve the Cornell box and write the result as .vtp (the README's Python example).

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/solve_cornell.py [OUT.vtp]
"""
import sys

import penumbra
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

result = penumbra.solve("cornell", threads=2)      # or a .vtp/.obj path, or a vtkPolyData
print(result.GetNumberOfPolys(), "triangles, unshot",
      result.GetFieldData().GetArray("UnshotFraction").GetValue(0))
writer = vtkXMLPolyDataWriter()
writer.SetInputData(result)
writer.SetFileName(sys.argv[1] if len(sys.argv) > 1 else "cornell.vtp")
writer.Write()
