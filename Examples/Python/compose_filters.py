# SPDX-License-Identifier: GPL-3.0-or-later
"""The Penumbra filters composed by hand: mesh, evaluate, reconstruct, write.

    PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Examples/Python/compose_filters.py seven out.vtp
"""
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

import penumbra

scene = penumbra.vtkPenumbraSceneSource()
scene.SetSceneName(sys.argv[1] if len(sys.argv) > 1 else "seven")

mesher = penumbra.vtkPenumbraDiscontinuityMesher()   # shadow and contact boundaries
mesher.SetInputConnection(scene.GetOutputPort())
mesher.SetMinimumAngle(20.0)

evaluator = penumbra.vtkPenumbraRadianceEvaluator()  # exact radiance at the samples
evaluator.SetInputConnection(0, mesher.GetOutputPort())
evaluator.SetSceneConnection(scene.GetOutputPort())

reconstructor = penumbra.vtkPenumbraRadianceReconstructor()  # C1 cubic, never negative
reconstructor.SetInputConnection(evaluator.GetOutputPort())

writer = vtkXMLPolyDataWriter()
writer.SetInputConnection(reconstructor.GetOutputPort())
writer.SetDataModeToBinary()  # inline data: what every ParaView reads
writer.SetFileName(sys.argv[2] if len(sys.argv) > 2 else "out.vtp")
writer.Write()
print("wrote", writer.GetFileName())
