"""Out-of-range element indices are reported with the value given, whatever its dtype.

Casting to int64 before the range check turned a uint64 ``2**64 - 1`` into
``-1`` and a float ``2**63`` into ``-2**63`` in the message.
"""

import numpy as np
import pytest

import heatcore as hc
from heatcore.domains.validate import index_array
from heatcore.errors import InvalidMeshError

V3 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
V4 = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)


@pytest.mark.parametrize(
    "value, dtype, shown",
    [
        (2**64 - 1, np.uint64, "18446744073709551615"),
        (2**63, np.uint64, "9223372036854775808"),
        (2**63 - 1, np.int64, "9223372036854775807"),
        (-(2**63), np.int64, "-9223372036854775808"),
        (2.0**63, np.float64, "9223372036854775808"),
        (2.0**64, np.float64, "18446744073709551616"),
        (3, np.uint8, "3"),
    ],
)
def test_triangle_mesh_message_shows_the_index_given(value, dtype, shown):
    F = np.array([[0, 1, value]], dtype=dtype)
    with pytest.raises(InvalidMeshError) as info:
        hc.TriangleMesh(V3, F)
    assert str(info.value) == (
        f"face 0 references vertex {shown} but the mesh has 3 vertices (valid indices are 0..2)"
    )


def test_tet_mesh_message_shows_the_index_given():
    T = np.array([[0, 1, 2, 3], [0, 1, 2, 2**64 - 1]], dtype=np.uint64)
    with pytest.raises(InvalidMeshError) as info:
        hc.TetMesh(V4, T)
    assert str(info.value) == (
        "tet 1 references vertex 18446744073709551615 but the mesh has 4 vertices (valid indices are 0..3)"
    )


def test_valid_unsigned_indices_are_accepted_as_int64():
    F = index_array(np.array([[0, 1, 2]], dtype=np.uint64), 3, 3)
    assert F.dtype == np.int64 and F.tolist() == [[0, 1, 2]]
    F = index_array(np.array([[0.0, 1.0, 2.0]]), 3, 3)
    assert F.dtype == np.int64 and F.tolist() == [[0, 1, 2]]
