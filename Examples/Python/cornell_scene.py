# SPDX-License-Identifier: GPL-3.0-or-later
"""Build the Cornell box, check it against the data contract, write it as .vtp.

Run with Debian's Python and the package on the path, e.g.
    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/cornell_scene.py out.vtp
"""
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import penumbra

source = penumbra.vtkPenumbraSceneSource()
source.SetSceneName("cornell")
validator = penumbra.vtkPenumbraSceneValidator()
validator.SetInputConnection(source.GetOutputPort())

writer = vtkXMLPolyDataWriter()
writer.SetInputConnection(validator.GetOutputPort())
writer.SetDataModeToBinary()  # inline data: what every ParaView reads
writer.SetFileName(sys.argv[1] if len(sys.argv) > 1 else "cornell.vtp")
writer.Write()
print("wrote", writer.GetFileName(), "with",
      validator.GetOutput().GetNumberOfCells(), "surfaces")
