"""Coverage-guided fuzzing of every reader with atheris (libFuzzer), under the contract of
``helpers.reader_fuzz``: the 2D readers, the 3D ones (TetGen, Geomview OFF of a Mesh3,
VTU/VTK tetrahedra) and meshio's.  The first input byte chooses the seed case (and so
the reader), the rest is the content of its main file; the case's other files stay valid.

    PYTHONPATH=tests python tests/io/fuzz_readers.py CORPUS_DIR -runs=100000

``CORPUS_DIR`` is filled with the valid seeds when empty.  ``test_io_fuzz_atheris.py``
runs a short sampled session in CI (``--runslow``: a longer one).  Not a pytest module.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path
from typing import Any

CASES: tuple[Any, ...] = ()  # the seed cases, set by main() (imported under instrumentation)


def write_corpus(directory: Path) -> None:
    """One file per seed case: its index byte, then its main file."""
    directory.mkdir(parents=True, exist_ok=True)
    if any(directory.iterdir()):
        return
    for index, case in enumerate(CASES):
        (directory / f"{index:02d}-{case.name}").write_bytes(
            bytes([index]) + case.files[case.main]
        )


def test_one_input(data: bytes) -> None:
    from helpers.reader_fuzz import check_read

    if not data:
        return
    case = CASES[data[0] % len(CASES)]
    files = dict(case.files)
    files[case.main] = data[1:]
    with tempfile.TemporaryDirectory() as directory:
        check_read(Path(directory), case, files)


def main() -> None:
    global CASES
    import atheris  # only here: importing this module (pytest's doctest pass) needs none

    with atheris.instrument_imports(include=["geomexact"]):
        from helpers.reader_fuzz import meshio_seeds, seeds, seeds3d
    CASES = (*seeds(), *seeds3d(), *meshio_seeds())
    corpus = [argument for argument in sys.argv[1:] if not argument.startswith("-")]
    if corpus:
        write_corpus(Path(corpus[0]))
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()


if __name__ == "__main__":
    main()
