"""The device file (``.device``): boxes of materials for the octree mesher, a line each
(``specs/formats/device.md``).

UTF-8 text; ``#`` starts a comment; blank lines are ignored; the first non-comment line
is the header ``geomexact-device 1``; then, in any order::

    material ID NAME            (a positive integer id and a name without spaces)
    box X0 Y0 Z0 X1 Y1 Z1 ID    (exact numbers: integers, decimals, p/q; X0 < X1, …)

Boxes are painted in file order: where two overlap, the later one wins.  Every problem
is a :class:`~geomexact.errors.FormatError` naming the file and the line."""

from __future__ import annotations

from pathlib import Path

from geomexact.errors import FormatError, PreconditionError, RationalParseError
from geomexact.io.files import read_lines, write_lines_atomic
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.device import Device, DeviceBox

__all__ = ["DEVICE_HEADER", "read_device", "write_device"]

DEVICE_HEADER = "geomexact-device 1"


def _material(path: str, number: int, text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise FormatError(path, number, f"the material id {text!r} is not an integer"
                          ) from None
    if value <= 0:
        raise FormatError(path, number, f"the material id is positive, not {value}")
    return value


def read_device(path: str | Path) -> Device:
    """The device of ``path`` (module docstring)."""
    name = str(path)
    header_seen = False
    boxes: list[DeviceBox] = []
    names: dict[int, str] = {}
    for number, raw in read_lines(path):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        tokens = text.split()
        if not header_seen:
            if " ".join(tokens) != DEVICE_HEADER:
                raise FormatError(name, number, f"the first line is {DEVICE_HEADER!r}, not "
                                  f"{text!r}")
            header_seen = True
            continue
        if tokens[0] == "material":
            if len(tokens) != 3:
                raise FormatError(name, number, "a material line is 'material ID NAME'")
            material = _material(name, number, tokens[1])
            if material in names:
                raise FormatError(name, number, f"material {material} is named twice")
            names[material] = tokens[2]
        elif tokens[0] == "box":
            if len(tokens) != 8:
                raise FormatError(name, number, "a box line is 'box X0 Y0 Z0 X1 Y1 Z1 ID' "
                                  f"(8 fields), not {len(tokens)} fields")
            try:
                values = [parse_rational(token) for token in tokens[1:7]]
            except RationalParseError as error:
                raise FormatError(name, number, str(error)) from None
            try:
                box = Box(values[:3], values[3:])
            except PreconditionError:
                raise FormatError(name, number, "a box needs X0 < X1, Y0 < Y1 and Z0 < Z1"
                                  ) from None
            boxes.append(DeviceBox(box, _material(name, number, tokens[7])))
        else:
            raise FormatError(name, number, f"a line is 'material …' or 'box …', not "
                              f"{tokens[0]!r}")
    if not header_seen:
        raise FormatError(name, None, f"empty: a device file starts with {DEVICE_HEADER!r}")
    if not boxes:
        raise FormatError(name, None, "the device has no box")
    unknown = sorted(set(names) - {item.material for item in boxes})
    if unknown:
        raise FormatError(name, None, f"materials {unknown} are named but no box has them")
    return Device(tuple(boxes), tuple(sorted(names.items())))


def write_device(path: str | Path, device: Device) -> None:
    """Write ``device`` to ``path`` (exact numbers; refusing to replace a file)."""
    lines = [DEVICE_HEADER]
    lines += [f"material {material} {label}" for material, label in device.names]
    lines += ["box " + " ".join(format_rational(v) for v in (*item.box.low, *item.box.high))
              + f" {item.material}" for item in device.boxes]
    write_lines_atomic(path, iter(lines), overwrite=False)
