"""Reading and writing files safely: UTF-8 text with clear errors, atomic writes that
never replace an existing file unless asked; gzip-compressed text read and written as a
stream, with the same bytes for the same text (no time stamp, no file name)."""

from __future__ import annotations

import errno
import gzip
import io
import os
import tempfile
import zlib
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


GZIP_MAGIC = b"\x1f\x8b"
"""The first two bytes of every gzip file: how :func:`read_lines` recognises one."""

GZIP_LEVEL = 6
"""The compression level of :func:`gzip_chunks` (fixed: the bytes depend on it)."""


def read_lines(path: str | Path, *, decompress: bool = False) -> Iterator[tuple[int, str]]:
    """The lines of the UTF-8 file ``path``, one at a time, as (1-based number, text
    without its ``\\n``), a leading byte-order mark removed: a long file is never held in
    memory whole, and a reader that stops at a bad line reads no further.  Lines are split
    on ``\\n`` only (``\\r`` stays in the text).  Errors are those of :func:`read_text`,
    raised when the iteration starts (missing file) or reaches the line (a bad byte).

    With ``decompress``, a file that starts with the gzip magic bytes (whatever its name)
    is decompressed as it is read; corrupt or truncated gzip data is a
    :class:`FormatError` naming the line being read when it was found."""
    name = str(path)
    try:
        handle = open(path, "rb")  # noqa: SIM115 - the generator owns it, closed by `with`
    except OSError as error:
        raise _unreadable(name, error) from error
    number = 0
    offset = 0
    with handle:
        source: Iterable[bytes] = handle
        compressed = False
        try:
            if decompress and handle.peek(2)[:2] == GZIP_MAGIC:
                compressed = True
                source = gzip.GzipFile(fileobj=handle, mode="rb")
            for number, data in enumerate(source, start=1):
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
        except (gzip.BadGzipFile, zlib.error) as error:
            raise FormatError(name, number + 1, f"corrupt gzip data ({error})") from error
        except EOFError as error:
            raise FormatError(
                name, number + 1, "truncated gzip file: the compressed data ends early"
            ) from error
        except OSError as error:
            if compressed and error.strerror is None:  # gzip's own complaint
                raise FormatError(name, number + 1, f"corrupt gzip data ({error})") from error
            raise FormatError(name, number or None, f"cannot read: {error.strerror}") from error


def gzip_chunks(chunks: Iterable[bytes]) -> Iterator[bytes]:
    """``chunks`` gzip-compressed, as they come: no modification time and no file name in
    the header, so the same data always gives the same bytes."""
    buffer = io.BytesIO()
    with gzip.GzipFile(filename="", mode="wb", fileobj=buffer, mtime=0,
                       compresslevel=GZIP_LEVEL) as packed:
        for chunk in chunks:
            packed.write(chunk)
            if buffer.tell():
                yield buffer.getvalue()
                buffer.seek(0)
                buffer.truncate()
    yield buffer.getvalue()


def write_text_atomic(path: str | Path, text: str, *, overwrite: bool = False) -> None:
    """Write ``text`` to ``path`` through a temporary file in the same directory and an
    atomic rename.  Raises :class:`OverwriteError` when ``path`` exists and not
    ``overwrite``; a failed write leaves any existing file untouched."""
    write_chunks_atomic(path, (text.encode("utf-8"),), overwrite=overwrite)


def write_bytes_atomic(path: str | Path, data: bytes, *, overwrite: bool = False) -> None:
    """Bytes version of :func:`write_text_atomic`."""
    write_chunks_atomic(path, (data,), overwrite=overwrite)


def write_lines_atomic(
    path: str | Path, lines: Iterable[str], *, overwrite: bool = False, compress: bool = False
) -> None:
    """:func:`write_text_atomic` for text given line by line (each without its newline),
    written as it comes: a long file is never held in memory whole.  With ``compress``
    the file is gzip-compressed (:func:`gzip_chunks`)."""
    chunks: Iterable[bytes] = ((line + "\n").encode("utf-8") for line in lines)
    if compress:
        chunks = gzip_chunks(chunks)
    write_chunks_atomic(path, chunks, overwrite=overwrite)


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
