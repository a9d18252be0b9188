"""Tooltips of the heatcore options as a Blender user reads them.

heatcore declares one help text per option (``heatcore.options``), written
for every front end: it starts lower-case and may name things a Blender user
cannot see (the command line's PNG picture, the ``fast`` extra, modules of
heatcore). :func:`option_help` gives the Blender tooltip of an option: the
text of :data:`OPTION_HELP` where the declared one does not fit, else the
declared text as a sentence. :data:`CHOICE_HELP` does the same for menu
entries. :data:`FOREIGN_WORDS` are the words no tooltip of the add-on holds
(the tests walk every registered property for them).

Examples
--------
>>> option_help("m", "heat time factor: t = m * h^2")
'Heat time factor: t = m * h^2'
>>> sentence("smooth: the heat method")
'Smooth: the heat method'
"""

import importlib

from ._heatcore import heatcore

#: What ``accuracy="high"`` costs in Blender (the extension does not bundle numba), declared once in heatcore.
_HIGH_COST = "-".join(f"{x:g}" for x in importlib.import_module(heatcore.__name__ + ".options")
                      .HIGH_ACCURACY_COST["vectorized"])

#: Words of other front ends or of heatcore's internals, which no tooltip of the add-on holds.
FOREIGN_WORDS = ("png", "picture", "numba", "extra", "heatcore.", "pip ", "command line", "--")

#: Blender tooltips of the heatcore options whose declared help names other front ends or internals,
#: or reads better for a Blender user in other words.
OPTION_HELP = {
    "m": "Heat time factor: the heat flows for m times the squared mean edge length; larger values give a "
         "smoother distance, smaller ones follow the surface more closely",
    "boundary": "How the heat behaves at open edges of the mesh (holes, borders): Robin, the mean of the two "
                "others, is recommended",
    "accuracy": "Smooth: the heat method (about 1-2% error, fastest); High: a second, eikonal pass (about 0.1-0.3% "
                f"error; a distance takes {_HIGH_COST} times as long to compute)",
    "backend": "Library that factors the solver's matrices: Auto picks the fastest one installed for the mesh "
               "size; the results are the same",
    "robust": "Intrinsic Delaunay operators: accurate on thin or badly shaped triangles; off: plain cotan "
              "operators on the mesh's own triangles (faster to build, much less accurate on poor meshes)",
    "refine": "Subdivide the mesh internally before solving (Auto: small parts, under 11,000 vertices, are "
              "refined); the distance is still written to the mesh's own vertices",
    "colormap": "Colormap of the distance colors (dark near the sources, bright far away)",
    "isolines": "Number of evenly spaced isolines, shown as dark stripes in the distance colors and as the "
                "isoline material's lines (0: none)",
    "weight_radius": "Geodesic distance at which the weight reaches 0 (it is 1 at the sources); 0: the largest "
                     "distance",
    "weight_falloff": "Curve of the weight from 1 at the sources to 0 at the radius (as in the Vertex Weight "
                      "Proximity modifier)",
}

#: Blender tooltips of menu entries of heatcore options, by (option, choice).
CHOICE_HELP = {
    ("backend", "gpu"): "NVIDIA GPU (cuDSS), for millions of vertices (listed only where Blender's Python has the "
                        "CUDA libraries and a GPU)",
    ("backend", "supernodal"): "CHOLMOD's supernodal Cholesky (cvxopt): fastest factorization of large meshes",
    ("backend", "cholmod"): "CHOLMOD (cholespy): the fastest solves",
}


def sentence(text):
    """``text`` with its first letter upper-case (the rest as it is)."""
    return text[:1].upper() + text[1:] if text else text


def option_help(name, declared):
    """The Blender tooltip of heatcore option ``name`` whose declared help is ``declared``."""
    return OPTION_HELP.get(name) or sentence(declared)


def choice_help(name, choice, declared):
    """The Blender tooltip of the menu entry ``choice`` of option ``name``."""
    return CHOICE_HELP.get((name, choice)) or sentence(declared)
