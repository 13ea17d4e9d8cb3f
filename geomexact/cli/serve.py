"""``geomexact serve``: serve a directory's meshes in the viewer, and refine uploads, over
local HTTP."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from geomexact.cli.arguments import Subcommands, add_command, non_negative, positive_float
from geomexact.cli.exit_codes import EXIT_OK


def command_serve(args: argparse.Namespace) -> int:
    """Serve a directory's meshes in the viewer, and refine uploads, until Ctrl-C."""
    from geomexact import server as serving

    options = serving.ServeOptions(
        Path(args.directory), host=args.host, port=args.port,
        max_upload_bytes=int(args.max_upload_mb * 1024 * 1024),
        time_limit=args.time_limit, jobs=args.jobs, view_jobs=args.view_jobs,
        memory_limit_bytes=(args.memory_limit_mb * 1024 * 1024
                            if args.memory_limit_mb else None),
    )
    if not serving.is_loopback(args.host):
        print(f"geomexact: warning: listening on {args.host}: other machines can read the "
              "served files and run jobs (there is no authentication)", file=sys.stderr)

    def announce(url: str) -> None:
        print(f"serving {options.directory} at {url} (Ctrl-C stops)", flush=True)

    try:
        serving.serve(options, announce=announce)
    except KeyboardInterrupt:
        print("stopped", file=sys.stderr)
    return EXIT_OK


def add_parser(commands: Subcommands) -> None:
    """Add the ``serve`` command."""
    serve_ = add_command(commands, "serve", command_serve)
    serve_.add_argument("directory", nargs="?", default=".", metavar="DIR",
                        help="directory whose mesh files are listed (default: .)")
    serve_.add_argument("--host", default="127.0.0.1",
                        help="interface to listen on (default 127.0.0.1, this machine only; "
                             "0.0.0.0 or an address opens it to the network)")
    serve_.add_argument("--port", type=non_negative, default=8765,
                        help="port (default 8765; 0 picks a free one)")
    serve_.add_argument("--max-upload-mb", type=positive_float, default=16, metavar="MB",
                        help="largest upload accepted (default 16)")
    serve_.add_argument("--time-limit", type=positive_float, default=60, metavar="SECONDS",
                        help="a job (reading, refining, building a page) is stopped after "
                             "this long (default 60)")
    serve_.add_argument("--jobs", type=non_negative, default=2, metavar="N",
                        help="upload jobs run at once; more uploads are told the server is "
                             "busy (default 2)")
    serve_.add_argument("--view-jobs", type=non_negative, default=2, metavar="N",
                        help="viewing jobs run at once, apart from the upload jobs (uploads "
                             "never make viewing busy); more are told the server is busy "
                             "(default 2)")
    serve_.add_argument("--memory-limit-mb", type=non_negative, default=2048,
                        metavar="MB",
                        help="a job's process may use at most this much memory (its "
                             "address space); 0: no limit (default 2048)")
