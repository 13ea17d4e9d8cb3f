"""``geomexact view``: the offline HTML viewer, or a PNG/SVG/PDF picture, of a mesh (and
trace)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_input_argument,
    add_output_option,
    add_reading_options,
    non_negative,
)
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_OK
from geomexact.cli.loading import Loaded, load, material_cells
from geomexact.cli.reporting import print_json
from geomexact.errors import GeomexactError
from geomexact.io.cell_arrays import MATERIAL_ARRAYS
from geomexact.io.files import staged_path
from geomexact.io.trace_file import read_trace
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.trace.record import Trace

if TYPE_CHECKING:
    import numpy as np

    from geomexact.viz.scene3d import Clip

VIEW_FILL_CHOICES = ("none", "min-angle", "area", "region", "material")


def command_view(args: argparse.Namespace) -> int:
    """Write the HTML viewer (``.html``) or a picture (``.png``, ``.svg``, ``.pdf``) of a
    mesh, PSLG, polygon mesh, tetrahedral or mixed-cell mesh; with ``--trace``, of the
    trace replayed on it."""
    from geomexact.io.files import write_text_atomic
    from geomexact.viz import pictures, viewer
    from geomexact.viz.scene import DEFAULT_EXACT_BUDGET

    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix not in (".html", ".htm", *pictures.PICTURE_FORMATS):
        raise UsageProblem(f"{output}: the output must end in .html, .png, .svg or .pdf")
    if args.step is not None and not args.trace:
        raise UsageProblem("--step needs --trace")
    loaded = load(args.input, args.format, args.verbose)
    value = loaded.value
    if args.clip is not None and not isinstance(value, Mesh3 | MixedMesh3):
        raise UsageProblem(f"{args.input}: --clip needs a tetrahedral mesh or a mixed-cell "
                           "mesh (3D)")
    trace = read_trace(args.trace) if args.trace else None
    fill = args.color_by.replace("-", "_")
    materials = _materials(args, loaded, fill, suffix in (".html", ".htm"))
    try:
        if isinstance(value, Mesh3 | MixedMesh3):
            _view_mesh3(args, value, trace, output, fill, materials)
        elif suffix in (".html", ".htm"):
            text = viewer.viewer_html(
                value, trace=trace, title=args.title, source=Path(args.input).name,
                trace_source=Path(args.trace).name if args.trace else None, fill=fill,
                step=args.step, exact_budget=0 if args.no_exact else DEFAULT_EXACT_BUDGET,
                notes=loaded.notes,
            )
            write_text_atomic(output, text, overwrite=args.force)
        elif trace is not None:
            pictures.plot_step(value, trace, args.step, output, overwrite=args.force,
                               title=args.title, color_by=fill)
        else:
            pictures.plot(value, output, overwrite=args.force, title=args.title,
                          color_by=fill)
    except (TypeError, ValueError) as error:
        if isinstance(error, GeomexactError):
            raise
        raise UsageProblem(f"{args.input}: {error}") from None
    report = {
        "input": args.input,
        "format": loaded.format,
        "kind": loaded.kind,
        "trace": args.trace,
        "steps": len(trace) if trace is not None else None,
        "step": args.step if args.step is not None else (
            len(trace) if trace is not None else None),
        "clip": None if args.clip is None else {"axis": args.clip[0],
                                                "position": args.clip[1]},
        "output": str(output),
        "bytes": staged_path(output).stat().st_size,  # appears when the command ends
    }
    if args.json:
        print_json(report)
    else:
        print(f"wrote {output}")
    return EXIT_OK


def _materials(args: argparse.Namespace, loaded: Loaded, fill: str, page: bool
               ) -> np.ndarray | None:
    """Each cell's material for ``--color-by material`` (a :class:`UsageProblem` naming
    the file when it has none, or is no 3D mesh, or comes with a trace); for a page
    without a trace, the materials when the file has them (its colour menu offers them);
    else None."""
    asked = fill == "material"
    if not asked and (not page or args.trace):
        return None
    if asked and not isinstance(loaded.value, Mesh3 | MixedMesh3):
        raise UsageProblem(f"{args.input}: --color-by material needs a tetrahedral or "
                           "mixed-cell mesh with a material cell array")
    if asked and args.trace:
        raise UsageProblem("--color-by material colours a mesh's cells: it does not go with "
                           "--trace")
    found = material_cells(loaded)
    if found is None:
        if asked:
            raise UsageProblem(f"{args.input}: has no integer cell array named "
                               f"{', '.join(MATERIAL_ARRAYS)}: --color-by material has "
                               "nothing to colour by")
        return None
    return found[1]


def _clip_of(args: argparse.Namespace) -> Clip | None:
    from geomexact.viz.scene3d import clip_plane

    if args.clip is None:
        return None
    axis, position = args.clip
    try:
        return clip_plane(axis, position)
    except ValueError as error:
        raise UsageProblem(f"--clip: {error}") from None


def _view_mesh3(args: argparse.Namespace, mesh: Mesh3 | MixedMesh3, trace: Trace | None,
                output: Path, fill: str, materials: np.ndarray | None) -> None:
    """The page or the picture of a tetrahedral or mixed-cell mesh (with a trace: the page
    steps through it; the picture draws the mesh after step ``--step``, default the
    last).  A tetrahedral mesh is coloured by radius ratio (``min-angle``) or plain, a
    mixed one by cell kind, either by ``materials`` (each cell's) for ``material``; the
    page carries ``materials`` when given."""
    from geomexact.io.files import write_text_atomic

    clip = _clip_of(args)
    title = args.title or Path(args.input).name
    mixed = isinstance(mesh, MixedMesh3)
    if output.suffix.lower() in (".html", ".htm"):
        from geomexact.viz.scene3d import viewer_html_3d

        # the 2D fills name triangle measures; in 3D, quality (radius ratio), kind or plain
        colour = ("plain" if fill in ("area", "region") else "material"
                  if fill == "material" else "kind" if mixed else "quality")
        text = viewer_html_3d(mesh, trace, title=title, colour=colour, step=args.step,
                              clip=clip, materials=materials)
        write_text_atomic(output, text, overwrite=args.force)
        return
    from geomexact.trace.playback import replay
    from geomexact.viz.pictures3d import plot_mesh3

    if fill == "material":
        plot_mesh3(mesh, output, overwrite=args.force, title=args.title, clip=clip,
                   colour="material", materials=materials)
        return
    if mixed and fill != "none":
        raise UsageProblem(f"--color-by {args.color_by} has no meaning for a mixed-cell "
                           "mesh's picture: its faces are coloured by cell kind")
    if fill in ("area", "region"):
        raise UsageProblem(f"--color-by {args.color_by} has no meaning for a tetrahedral "
                           "mesh's picture: none (plain) or min-angle (radius ratio)")
    if trace is not None:
        if args.step is not None and args.step > len(trace):
            raise UsageProblem(f"--step {args.step} is beyond the trace's {len(trace)} steps")
        mesh = replay(mesh, trace, until=args.step)
    plot_mesh3(mesh, output, overwrite=args.force, title=args.title, clip=clip,
               colour="kind" if mixed else "quality" if fill == "min_angle" else "plain")


def add_parser(commands: Subcommands) -> None:
    """Add the ``view`` command."""
    view = add_command(commands, "view", command_view)
    add_input_argument(view, "mesh, PSLG or polygon mesh (with --trace: the trace's input)")
    add_output_option(view, "OUT.html: the viewer; OUT.png, .svg or .pdf: a picture",
                      required=True)
    view.add_argument("--trace", metavar="TRACE",
                      help="a trace recorded on INPUT: the viewer gets a step slider")
    view.add_argument("--step", type=non_negative, metavar="K",
                      help="with --trace: the step shown first (viewer) or drawn (picture); "
                           "default: the last")
    view.add_argument("--color-by", choices=VIEW_FILL_CHOICES, default="none",
                      help="fill triangles by smallest angle, area or region attribute; "
                           "tetrahedra: min-angle colours by radius ratio; 3D meshes: "
                           "material colours cells by their integer cell array "
                           f"{', '.join(MATERIAL_ARRAYS)} (the first present), with a "
                           "legend")
    view.add_argument("--clip", nargs=2, metavar=("AXIS", "POSITION"),
                      help="3D meshes: remove the cells whose centroid (mean of their "
                           "vertices) is beyond the plane AXIS (x, y or z) = POSITION "
                           "(exact: 1/2, 0.25) and show the faces it opens; the page starts "
                           "with it")
    view.add_argument("--title", help="title of the page or picture")
    view.add_argument("--no-exact", action="store_true",
                      help="leave the exact coordinates out of the page (smaller file)")
    add_reading_options(view, force="an existing OUT")
