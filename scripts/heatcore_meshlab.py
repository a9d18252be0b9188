#!/usr/bin/env python3
"""Geodesic distance from a MeshLab selection: thin wrapper around :func:`heatcore.apps.meshlab.main`.

Usage (see docs/meshlab.md)::

    python scripts/heatcore_meshlab.py mesh.ply -o mesh_distance.ply
    python scripts/heatcore_meshlab.py mesh.obj --sources 0 17 --isolines 12
    python scripts/heatcore_meshlab.py mesh.obj --select "(y > 0.9)"
"""

import sys

from heatcore.apps.meshlab import main

if __name__ == "__main__":
    sys.exit(main(prog="heatcore_meshlab.py"))
