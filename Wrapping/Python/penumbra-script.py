#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The `penumbra` command. Finds the penumbra package beside its own prefix."""
import os
import sys

_prefix = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
sys.path.insert(0, os.path.join(_prefix, "lib", "python3", "dist-packages"))

from penumbra.cli import main  # noqa: E402

sys.exit(main())
