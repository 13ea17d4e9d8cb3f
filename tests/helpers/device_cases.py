"""A small device for the tests: a MOS capacitor whose layers lie on the quarter
lattice (substrate 1/2, oxide 1/4, gate 1/16 of the unit cube's volume), as a device
file's text and as a value."""

from __future__ import annotations

from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.device import Device, DeviceBox

MOS_DEVICE = """geomexact-device 1
# substrate, oxide, gate
material 1 silicon
material 2 oxide
material 3 metal
box 0 0 0 1 1 0.5 1
box 0 0 0.5 1 1 0.75 2
box 0.25 0.25 0.75 0.75 0.75 1 3
"""


def mos() -> Device:
    """The device of :data:`MOS_DEVICE`."""
    return Device((
        DeviceBox(Box((0, 0, 0), (1, 1, mpq(1, 2))), 1),
        DeviceBox(Box((0, 0, mpq(1, 2)), (1, 1, mpq(3, 4))), 2),
        DeviceBox(Box((mpq(1, 4), mpq(1, 4), mpq(3, 4)), (mpq(3, 4), mpq(3, 4), 1)), 3),
    ), ((1, "silicon"), (2, "oxide"), (3, "metal")))
