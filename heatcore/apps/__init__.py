"""Front ends: the command line, batch runs and the MeshLab filter. They hold no numerics.

Front ends import the core; the core never imports them.
"""
