"""Reading and writing files safely: UTF-8 text with clear errors, atomic writes that
never replace an existing file unless asked; gzip-compressed text read and written as a
stream, with the same bytes for the same text (no time stamp, no file name)."""

from __future__ import annotations

import errno
import gzip
import io
import os
import stat
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


def _not_regular(mode: int) -> str | None:
    """Why a file of ``mode`` (``st_mode``) is not read, or None for a regular file."""
    if stat.S_ISREG(mode):
        return None
    if stat.S_ISDIR(mode):
        return "is a directory, not a file"
    kinds = ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
             (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))
    kind = next((label for test, label in kinds if test(mode)), "a file of an unknown kind")
    return f"not a regular file: {kind}; only regular files are read"


def check_regular(path: str | Path) -> None:
    """:class:`FormatError` unless ``path`` is a regular file (or a link to one), decided
    by ``os.stat`` without opening it: a missing file, a directory, a FIFO (opening one
    for reading waits for a writer), a device (``/dev/zero`` never ends) or a socket."""
    name = str(path)
    try:
        mode = os.stat(path).st_mode
    except OSError as error:
        raise _unreadable(name, error) from error
    problem = _not_regular(mode)
    if problem is not None:
        raise FormatError(name, None, problem)


_NONBLOCK = getattr(os, "O_NONBLOCK", 0)


def open_regular(path: str | Path) -> io.BufferedReader:
    """``path`` opened for binary reading once :func:`check_regular` accepts it.  It is
    opened without waiting (``O_NONBLOCK``) and checked again on the open file, so a file
    replaced by a FIFO in between is refused too; errors are :class:`FormatError`."""
    check_regular(path)
    name = str(path)
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0) | _NONBLOCK)
    except OSError as error:
        raise _unreadable(name, error) from error
    try:
        problem = _not_regular(os.fstat(descriptor).st_mode)
        if problem is not None:
            raise FormatError(name, None, problem)
        if _NONBLOCK:
            os.set_blocking(descriptor, True)
        return os.fdopen(descriptor, "rb")
    except BaseException:
        os.close(descriptor)
        raise


LINE_LIMIT = 1 << 24
"""The longest line (bytes, without its newline) :func:`read_lines` gives: 16 MiB, far
more than a line of any geomexact text format needs.  A longer line (a binary file, data
without newlines) is a :class:`FormatError` at that line, after reading at most this
much of it: memory stays bounded and the time linear whatever the file."""


def _limited_lines(stream: io.BufferedIOBase) -> Iterator[bytes]:
    """The lines of ``stream``, each with its newline, each of at most
    :data:`LINE_LIMIT` bytes plus the newline; a longer one is given cut, one byte over
    the limit and without a newline (the caller refuses it)."""
    while data := stream.readline(LINE_LIMIT + 1):
        yield data
        if len(data) > LINE_LIMIT and not data.endswith(b"\n"):
            return


def read_text(path: str | Path) -> str:
    """The UTF-8 text of ``path``; :class:`FormatError` for a missing, unreadable or
    non-UTF-8 file (naming the line of the first bad byte) and for anything but a regular
    file (:func:`check_regular`)."""
    name = str(path)
    try:
        with open_regular(path) as handle:
            data = handle.read()
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
    raised when the iteration starts (missing file, not a regular file) or reaches the
    line (a bad byte, a line longer than :data:`LINE_LIMIT`).

    With ``decompress``, a file that starts with the gzip magic bytes (whatever its name)
    is decompressed as it is read; corrupt or truncated gzip data is a
    :class:`FormatError` naming the line being read when it was found."""
    name = str(path)
    handle = open_regular(path)
    number = 0
    offset = 0
    with handle:
        source: io.BufferedIOBase = handle
        compressed = False
        try:
            if decompress and handle.peek(2)[:2] == GZIP_MAGIC:
                compressed = True
                source = gzip.GzipFile(fileobj=handle, mode="rb")
            for number, data in enumerate(_limited_lines(source), start=1):
                if len(data) > LINE_LIMIT and not data.endswith(b"\n"):
                    raise FormatError(
                        name, number, f"this line is longer than {LINE_LIMIT:,} bytes, more "
                        "than any line of a text mesh format needs (a binary file?)")
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
