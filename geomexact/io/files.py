"""Reading and writing files safely: UTF-8 text with clear errors, atomic writes that
never replace an existing file unless asked."""

from __future__ import annotations

import errno
import os
import tempfile
from collections.abc import Iterable, Iterator
from pathlib import Path

from geomexact.errors import FormatError, OverwriteError


def _unreadable(name: str, error: OSError) -> FormatError:
    """The FormatError for a file that cannot be opened."""
    if isinstance(error, FileNotFoundError):
        return FormatError(name, None, "no such file")
    if isinstance(error, IsADirectoryError):
        return FormatError(name, None, "is a directory, not a file")
    return FormatError(name, None, f"cannot read: {error.strerror}")


def read_text(path: str | Path) -> str:
    """The UTF-8 text of ``path``; :class:`FormatError` for a missing, unreadable or
    non-UTF-8 file (naming the line of the first bad byte)."""
    name = str(path)
    try:
        data = Path(path).read_bytes()
    except OSError as error:
        raise _unreadable(name, error) from error
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise FormatError(name, line, f"not UTF-8 text (byte {error.start})") from error


def read_lines(path: str | Path) -> Iterator[tuple[int, str]]:
    """The lines of the UTF-8 file ``path``, one at a time, as (1-based number, text
    without its ``\\n``), a leading byte-order mark removed: a long file is never held in
    memory whole, and a reader that stops at a bad line reads no further.  Lines are split
    on ``\\n`` only (``\\r`` stays in the text).  Errors are those of :func:`read_text`,
    raised when the iteration starts (missing file) or reaches the line (a bad byte)."""
    name = str(path)
    try:
        handle = open(path, "rb")  # noqa: SIM115 - the generator owns it, closed by `with`
    except OSError as error:
        raise _unreadable(name, error) from error
    number = 0
    offset = 0
    with handle:
        try:
            for number, data in enumerate(handle, start=1):
                try:
                    text = data.decode("utf-8")
                except UnicodeDecodeError as error:
                    raise FormatError(
                        name, number, f"not UTF-8 text (byte {offset + error.start})"
                    ) from error
                offset += len(data)
                if number == 1:
                    text = text.removeprefix("\ufeff")  # a byte-order mark is not data
                yield number, text.removesuffix("\n")
        except OSError as error:
            raise FormatError(name, number or None, f"cannot read: {error.strerror}") from error


def write_text_atomic(path: str | Path, text: str, *, overwrite: bool = False) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same directory and an
    atomic rename.  Raises :class:`OverwriteError` when ``path`` exists and not
    ``overwrite``; a failed write leaves any existing file untouched."""
    write_chunks_atomic(path, (text.encode("utf-8"),), overwrite=overwrite)


def write_bytes_atomic(path: str | Path, data: bytes, *, overwrite: bool = False) -> None:
    """Bytes version of :func:`write_text_atomic`."""
    write_chunks_atomic(path, (data,), overwrite=overwrite)


def write_lines_atomic(path: str | Path, lines: Iterable[str], *, overwrite: bool = False) -> None:
    """:func:`write_text_atomic` for text given line by line (each without its newline),
    written as it comes: a long file is never held in memory whole."""
    write_chunks_atomic(
        path, ((line + "\n").encode("utf-8") for line in lines), overwrite=overwrite
    )


def write_chunks_atomic(
    path: str | Path, chunks: Iterable[bytes], *, overwrite: bool = False
) -> None:
    """Write ``chunks`` one after the other, atomically, as :func:`write_text_atomic`."""
    target = Path(path)
    if target.exists() and not overwrite:
        raise OverwriteError(str(target))
    directory = target.parent if str(target.parent) else Path(".")
    if not directory.is_dir():
        raise FileNotFoundError(
            errno.ENOENT, f"cannot write {target}: directory {directory} does not exist"
        )
    descriptor, temporary = tempfile.mkstemp(
        prefix=f".{target.name}.", suffix=".tmp", dir=directory
    )
    try:
        with os.fdopen(descriptor, "wb") as handle:
            for chunk in chunks:
                handle.write(chunk)
        os.chmod(temporary, 0o666 & ~_umask())
        if not overwrite:
            # link() fails if the target appeared meanwhile: never clobber a file silently
            try:
                os.link(temporary, target)
            except FileExistsError as error:
                raise OverwriteError(str(target)) from error
            except OSError:
                os.replace(temporary, target)
                return
            os.unlink(temporary)
        else:
            os.replace(temporary, target)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def _umask() -> int:
    current = os.umask(0o022)
    os.umask(current)
    return current
