"""Reading and writing files safely: UTF-8 text with clear errors, atomic writes that
never replace an existing file unless asked; gzip-compressed text read and written as a
stream, with the same bytes for the same text (no time stamp, no file name)."""

from __future__ import annotations

import contextlib
import contextvars
import errno
import gzip
import hashlib
import io
import os
import shutil
import signal
import stat
import tempfile
import threading
import zlib
from collections.abc import Iterable, Iterator
from pathlib import Path

from geomexact.errors import FormatError, InputOverwriteError, OverwriteError


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
        status = os.stat(path)
    except OSError as error:
        raise _unreadable(name, error) from error
    problem = _not_regular(status.st_mode)
    if problem is not None:
        raise FormatError(name, None, problem)
    active = _ACTIVE_SET.get()
    if active is not None:
        active.note_input(Path(path), status)


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
    """Write ``chunks`` one after the other, atomically, as :func:`write_text_atomic`.
    Inside :func:`output_set` the file is staged and appears with the rest of the set."""
    active = _ACTIVE_SET.get()
    if active is not None:
        active.stage(path, chunks, overwrite=overwrite)
        return
    with output_set() as files:
        files.stage(path, chunks, overwrite=overwrite)


STAGING_PREFIX = ".geomexact-staging-"
"""The name of a hidden folder that holds an output set's files until they appear
together; it is followed by the writing process's id and a random part."""


class OutputSet:
    """Files that appear together: each is written whole, and flushed to the disk, into a
    hidden staging folder beside its target (:data:`STAGING_PREFIX`); :meth:`commit`
    then renames every one into place, and :meth:`discard` (any failure, Ctrl-C, a full
    disk) removes them all, leaving every target as it was.  Staging folders left by a
    process that was killed are removed by the next set that writes in that folder.

    A set is used once: :func:`output_set` makes one and ends it."""

    def __init__(self) -> None:
        self._staged: dict[Path, tuple[Path, bool]] = {}  # target -> (staged file, overwrite)
        self._folders: dict[Path, Path] = {}  # target directory -> its staging folder
        self._removals: list[Path] = []
        self._inputs: dict[tuple[int, int], Path] = {}  # (device, inode) -> path as read
        self._ended = False

    @property
    def targets(self) -> tuple[Path, ...]:
        """The files staged so far, in the order they were staged."""
        return tuple(self._staged)

    def note_input(self, path: Path, status: os.stat_result) -> None:
        """Remember that ``path`` (whose ``os.stat`` is ``status``) was read: no file of
        the set may replace it (:meth:`refuse_input`)."""
        self._inputs.setdefault((status.st_dev, status.st_ino), path)

    def refuse_input(self, path: str | Path) -> None:
        """:class:`InputOverwriteError` when ``path`` is a file this set's command read
        (the same file by any name: a link, another spelling of the path)."""
        try:
            status = os.stat(path)
        except OSError:
            return
        source = self._inputs.get((status.st_dev, status.st_ino))
        if source is not None:
            raise InputOverwriteError(str(path), str(source))

    def staged_path(self, path: str | Path) -> Path:
        """Where the staged copy of ``path`` is until the set is committed (``path``
        itself when the set holds no such file)."""
        entry = self._staged.get(_absolute(Path(path)))
        return entry[0] if entry is not None else Path(path)

    def stage(self, path: str | Path, chunks: Iterable[bytes], *, overwrite: bool) -> str:
        """Write ``chunks`` as the staged copy of ``path`` and return the BLAKE2b-128
        digest (hex) of what was written.  :class:`OverwriteError` when ``path`` exists
        and not ``overwrite``; an :class:`OSError` (a full disk, a folder that cannot be
        written) names ``path``, not the staging folder."""
        if self._ended:
            raise RuntimeError("this output set has ended")
        target = Path(path)
        self.refuse_input(target)
        if target.exists() and not overwrite:
            raise OverwriteError(str(target))
        directory = target.parent if str(target.parent) else Path(".")
        if not directory.is_dir():
            raise FileNotFoundError(
                errno.ENOENT, f"cannot write {target}: directory {directory} does not exist"
            )
        key = _absolute(target)
        staged = self._folder(key.parent, target) / target.name
        digest = hashlib.blake2b(digest_size=16)
        try:
            with open(staged, "wb") as handle:
                for chunk in chunks:
                    handle.write(chunk)
                    digest.update(chunk)
                handle.flush()
                os.fsync(handle.fileno())
            os.chmod(staged, 0o666 & ~_umask())
        except OSError as error:
            with contextlib.suppress(OSError):
                staged.unlink()
            raise _naming(error, target) from error
        self._staged[key] = (staged, overwrite)
        return digest.hexdigest()

    def append(self, path: str | Path, data: bytes) -> None:
        """Add ``data`` at the end of the staged copy of ``path`` (flushed to the disk)."""
        target = Path(path)
        staged = self._staged[_absolute(target)][0]
        try:
            with open(staged, "ab") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
        except OSError as error:
            raise _naming(error, target) from error

    def remove_with_commit(self, path: str | Path) -> None:
        """Remove ``path`` (when it exists) as the set is committed: a member of an earlier
        set at that name that this one does not write again (a stale ``.poly``)."""
        key = _absolute(Path(path))
        if key not in self._staged and key not in self._removals:
            self.refuse_input(key)
            self._removals.append(key)

    def commit(self) -> None:
        """Move every staged file into place (refusing first, before any move, a target
        that appeared meanwhile and may not be replaced), make the moves durable, and
        remove the staging folders.  An :class:`OSError` of a move names the target."""
        if self._ended:
            raise RuntimeError("this output set has ended")
        with _signals_deferred():
            self._commit()

    def _commit(self) -> None:
        self._ended = True
        try:
            for target, (_, overwrite) in self._staged.items():
                if not overwrite and os.path.lexists(target):
                    raise OverwriteError(str(target))
            for target, (staged, overwrite) in self._staged.items():
                try:
                    if overwrite:
                        os.replace(staged, target)
                    else:
                        _link_or_move(staged, target)
                except OverwriteError:
                    raise
                except OSError as error:  # e.g. the target is a directory
                    raise _naming(error, target) from error
            for target in self._removals:
                with contextlib.suppress(FileNotFoundError):
                    target.unlink()
            for directory in self._folders:
                _sync_directory(directory)
        finally:
            self._remove_folders()

    def discard(self) -> None:
        """Remove every staged file: no target is touched."""
        self._ended = True
        with _signals_deferred():
            self._remove_folders()

    def _folder(self, directory: Path, target: Path) -> Path:
        folder = self._folders.get(directory)
        if folder is None:
            _remove_abandoned_staging(directory)
            with _signals_deferred():  # a folder made is a folder remembered
                try:
                    folder = Path(tempfile.mkdtemp(
                        prefix=f"{STAGING_PREFIX}{os.getpid()}-", dir=directory))
                except OSError as error:
                    raise _naming(error, target) from error
                self._folders[directory] = folder
        return folder

    def _remove_folders(self) -> None:
        for folder in self._folders.values():
            shutil.rmtree(folder, ignore_errors=True)
        self._folders.clear()


_ACTIVE_SET: contextvars.ContextVar[OutputSet | None] = contextvars.ContextVar(
    "geomexact_output_set", default=None)


@contextlib.contextmanager
def output_set() -> Iterator[OutputSet]:
    """A new :class:`OutputSet` that every atomic write of this module stages into until
    the block ends: committed when the block ends normally, discarded when it raises
    (``KeyboardInterrupt`` included).  Sets do not nest: inside an active set the block
    shares it (and the outer block commits)."""
    active = _ACTIVE_SET.get()
    if active is not None:
        yield active
        return
    files = OutputSet()
    token = _ACTIVE_SET.set(files)
    try:
        yield files
    except BaseException:
        _ACTIVE_SET.reset(token)
        files.discard()
        raise
    _ACTIVE_SET.reset(token)
    files.commit()


def refuse_inputs(paths: Iterable[str | Path]) -> None:
    """:class:`InputOverwriteError` for the first of ``paths`` that the command in the
    active :func:`output_set` has read: checked before the work, and again as each file
    is written."""
    active = _ACTIVE_SET.get()
    if active is not None:
        for path in paths:
            active.refuse_input(path)


def staged_path(path: str | Path) -> Path:
    """Where ``path`` is readable now: its staged copy inside an active
    :func:`output_set` that holds it, else ``path`` itself."""
    active = _ACTIVE_SET.get()
    return active.staged_path(path) if active is not None else Path(path)


_DEFERRED = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Ctrl-C and SIGTERM wait until the block ends, then act as they would have: the
    renames of a commit all happen, and a staging folder made is one the set will
    remove.  Python's handlers run in the main thread only: elsewhere the block runs as
    it is."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []

    def defer(signum: int, frame: object) -> None:
        caught.append(signum)

    previous = {number: signal.signal(number, defer) for number in _DEFERRED}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler if handler is not None else signal.SIG_DFL)
        for caught_number in dict.fromkeys(caught):
            signal.raise_signal(caught_number)


def _absolute(path: Path) -> Path:
    return Path(os.path.abspath(path))


def _naming(error: OSError, target: Path) -> OSError:
    """``error`` as the same kind of OSError naming ``target`` (never a staging file)."""
    return type(error)(error.errno, error.strerror or str(error), str(target))


def _link_or_move(staged: Path, target: Path) -> None:
    """Move ``staged`` to ``target`` without ever replacing a file that appeared there
    (``link`` fails on an existing name; a file system without links is moved to)."""
    try:
        os.link(staged, target)
    except FileExistsError as error:
        raise OverwriteError(str(target)) from error
    except OSError:
        os.replace(staged, target)
        return
    os.unlink(staged)


def _sync_directory(directory: Path) -> None:
    """Make the renames in ``directory`` durable (where the system allows)."""
    try:
        descriptor = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(descriptor)
    except OSError:
        pass
    finally:
        os.close(descriptor)


def _remove_abandoned_staging(directory: Path) -> None:
    """Remove staging folders in ``directory`` whose writing process no longer runs (it
    was killed before it could clean up)."""
    try:
        names = [name for name in os.listdir(directory) if name.startswith(STAGING_PREFIX)]
    except OSError:
        return
    for name in names:
        pid_text = name[len(STAGING_PREFIX):].split("-", 1)[0]
        if not pid_text.isdigit() or _process_runs(int(pid_text)):
            continue
        shutil.rmtree(directory / name, ignore_errors=True)


def _process_runs(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _umask() -> int:
    current = os.umask(0o022)
    os.umask(current)
    return current
