"""The control-volume file (``.cv``): a Delaunay mesh's Voronoi control volumes as a
finite-volume solver reads them.  Specification: ``specs/formats/control_volumes.md``.

UTF-8 text, one record a line, tokens separated by one space, numbers exact (an integer
or finite decimal as such, any other rational as ``p/q``)::

    # geomexact control volumes 1
    vertices N
    <id> <x> <y> <z> <volume>                      (N lines, ids increasing)
    faces M
    <u> <v> <ax> <ay> <az> <coupling> <area> <adequate>   (M lines, edges sorted)

``ax ay az`` is the exact area vector of edge ``uv``'s Voronoi face, oriented from ``u``
to ``v``; ``coupling`` the exact ``|A| / |e|``; ``area`` the nearest double of ``|A|``
(``repr``); ``adequate`` ``1``, or ``0`` for a face pointing against its edge."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from geomexact.errors import FormatError, RationalParseError
from geomexact.io.files import read_lines, write_lines_atomic
from geomexact.kernel.numbers import Rational, format_rational, parse_rational
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.voronoi import ControlVolumes

__all__ = ["CONTROL_VOLUMES_HEADER", "read_control_volumes", "write_control_volumes"]

CONTROL_VOLUMES_HEADER = "# geomexact control volumes 1"


def control_volume_lines(mesh: Mesh3 | MixedMesh3, volumes: ControlVolumes) -> Iterator[str]:
    """The lines of the file (module docstring), without their newlines."""
    yield CONTROL_VOLUMES_HEADER
    yield f"vertices {len(volumes.volumes)}"
    for vertex, volume in sorted(volumes.volumes.items()):
        point = mesh.point(vertex)
        yield " ".join([str(vertex), *(format_rational(c) for c in point[:3]),
                        format_rational(volume)])
    yield f"faces {len(volumes.faces)}"
    for face in volumes.faces:
        yield " ".join([str(face.edge[0]), str(face.edge[1]),
                        *(format_rational(c) for c in face.area_vector),
                        format_rational(face.coupling), repr(face.area),
                        "1" if face.adequate else "0"])


def write_control_volumes(path: str | Path, mesh: Mesh3 | MixedMesh3, volumes: ControlVolumes, *,
                          overwrite: bool = False) -> None:
    """Write the control volumes of ``mesh`` to ``path`` atomically (refusing to replace
    a file unless ``overwrite``)."""
    write_lines_atomic(path, control_volume_lines(mesh, volumes), overwrite=overwrite)


def read_control_volumes(path: str | Path) -> tuple[dict[int, Rational],
                                                   dict[tuple[int, int], Rational]]:
    """The volumes by vertex and the couplings by edge of a ``.cv`` file; a
    :class:`FormatError` names the line of anything else."""
    name = str(path)
    lines = read_lines(path)
    volumes: dict[int, Rational] = {}
    couplings: dict[tuple[int, int], Rational] = {}

    def count(expected: str) -> int:
        number, text = next(lines, (0, ""))
        words = text.split()
        if len(words) != 2 or words[0] != expected or not words[1].isdigit():
            raise FormatError(name, number or None, f"expected '{expected} COUNT'")
        return int(words[1])

    number, text = next(lines, (1, ""))
    if text != CONTROL_VOLUMES_HEADER:
        raise FormatError(name, number, f"not a control-volume file (expected "
                          f"{CONTROL_VOLUMES_HEADER!r})")
    try:
        for _ in range(count("vertices")):
            number, text = next(lines)
            words = text.split()
            if len(words) != 5:
                raise FormatError(name, number, "expected 'id x y z volume'")
            volumes[int(words[0])] = parse_rational(words[4])
        for _ in range(count("faces")):
            number, text = next(lines)
            words = text.split()
            if len(words) != 8:
                raise FormatError(name, number, "expected 'u v ax ay az coupling area "
                                  "adequate'")
            couplings[(int(words[0]), int(words[1]))] = parse_rational(words[5])
    except StopIteration:
        raise FormatError(name, None, "the file ends before its records do") from None
    except FormatError:
        raise
    except (ValueError, RationalParseError) as error:
        raise FormatError(name, number, f"not a number: {error}") from error
    return volumes, couplings
