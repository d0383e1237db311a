#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The `penumbra` command. Finds the penumbra package relative to its own folder."""
import os
import sys

_here = os.path.dirname(os.path.realpath(__file__))
sys.path.insert(0, os.path.normpath(os.path.join(_here, "@PENUMBRA_PYTHON_FROM_BINDIR@")))

from penumbra.cli import main  # noqa: E402

sys.exit(main())
