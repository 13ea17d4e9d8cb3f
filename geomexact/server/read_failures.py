"""What a page says when reading a file fails: the file, the line and the kind of
problem, never the file's own text.

A reader's :class:`~geomexact.errors.FormatError` quotes the offending tokens
(``found 3 fields: 'root:x:0:0'``); its quoted phrases of the format's own vocabulary
(``a triangle line is 'x1 y1 x2 y2 x3 y3'``) help.  :func:`without_file_text` keeps a
quoted phrase only when none of its words occurs on the offending line of the file, and
shows :data:`NOT_SHOWN` instead of any other; other errors (meshio's, the operating
system's) are named by kind only."""

from __future__ import annotations

import ast
import itertools
import re
from pathlib import Path

NOT_SHOWN = "(text not shown)"
MAX_LINE_BYTES = 1 << 16  # a longer offending line is not searched: every quote is hidden

_LITERALS = {"'": re.compile(r"'(?:[^'\\\n]|\\.)*'"),
             '"': re.compile(r'"(?:[^"\\\n]|\\.)*"')}
_WORDS = re.compile(r"\w+")


def offending_line(path: str, number: int | None) -> str | None:
    """Line ``number`` (1-based) of the file ``path``, case-folded, in both numberings a
    reader uses (lines split on ``\\n``, and as ``str.splitlines`` splits them), joined;
    None when neither numbering has such a line, a line up to it is longer than
    :data:`MAX_LINE_BYTES` or the file cannot be read."""
    if number is None or number < 1:
        return None
    found: list[str] = []
    split_count = 0
    try:
        with open(path, "rb") as handle:
            for index in itertools.count(1):
                raw = handle.readline(MAX_LINE_BYTES + 1)
                if len(raw) > MAX_LINE_BYTES:
                    return None
                if not raw:  # the file ends: the line found in either numbering, if any
                    return "\n".join(found).casefold() if found else None
                text = raw.decode("utf-8", "replace")
                pieces = text.splitlines()
                if split_count < number <= split_count + len(pieces):
                    found.append(pieces[number - split_count - 1])
                split_count += len(pieces)
                if index == number:
                    found.append(text)
                if index >= number and split_count >= number:
                    return "\n".join(found).casefold()
    except OSError:
        return None
    return None  # pragma: no cover - itertools.count never ends


def _is_apostrophe(text: str, index: int) -> bool:
    """True for a ``'`` inside a word (``mesh's``), not for one opening ``b'…'``."""
    if text[index] != "'" or not 0 < index < len(text) - 1:
        return False
    before, after = text[index - 1], text[index + 1]
    lone_b = before in "bB" and (index < 2 or not text[index - 2].isalnum())
    return before.isalnum() and after.isalnum() and not lone_b


def _keeps(quoted: str, line: str | None) -> bool:
    if line is None:
        return False
    try:
        text = ast.literal_eval(quoted)
    except (ValueError, SyntaxError, MemoryError, RecursionError):
        return False
    words = _WORDS.findall(text.casefold()) if isinstance(text, str) else []
    return bool(words) and not any(word in line for word in words)


def without_file_text(problem: str, line: str | None) -> str:
    """``problem`` with every quoted phrase that may be the file's text replaced by
    :data:`NOT_SHOWN`: one is kept only when it is a plain string none of whose words
    (runs of letters and digits) occurs in ``line`` (the offending line, case-folded;
    None hides every quote).  An unclosed or bytes quote hides the rest of the problem."""
    shown: list[str] = []
    position = 0
    index = 0
    while index < len(problem):
        mark = problem[index]
        if mark not in _LITERALS or _is_apostrophe(problem, index):
            index += 1
            continue
        literal = _LITERALS[mark].match(problem, index)
        is_bytes = index > 0 and problem[index - 1] in "bB" and (
            index < 2 or not problem[index - 2].isalnum())
        shown.append(problem[position:index])
        if literal is None or is_bytes:
            shown.append(NOT_SHOWN)
            return "".join(shown)
        shown.append(literal.group(0) if _keeps(literal.group(0), line) else NOT_SHOWN)
        position = index = literal.end()
    shown.append(problem[position:])
    return "".join(shown)


def without_prefixes(text: str, prefixes: tuple[str, ...]) -> str:
    """``text`` with every occurrence of each of ``prefixes`` (folder paths ending with a
    separator) removed: the paths in it become relative."""
    for prefix in prefixes:
        text = text.replace(prefix, "")
    return text


def shown_path(path: str, prefixes: tuple[str, ...]) -> str:
    """``path`` without the first of ``prefixes`` it starts with (folders the user never
    named: the served directory, a sandbox, an upload's temporary folder)."""
    for prefix in prefixes:
        if path.startswith(prefix):
            return path[len(prefix):]
    return Path(path).name


def failure_message(error: BaseException, name: str, prefixes: tuple[str, ...]) -> str:
    """The page's message for ``error`` raised while reading the file shown as ``name``:
    ``file:line: problem`` for a :class:`~geomexact.errors.FormatError` (paths relative,
    quotes of the file's text hidden), the kind of problem for anything else."""
    from geomexact.errors import FormatError, GeomexactError

    if isinstance(error, FormatError):
        where = shown_path(error.path, prefixes)
        if error.line is not None:
            where = f"{where}:{error.line}"
        problem = without_file_text(without_prefixes(error.problem, prefixes),
                                    offending_line(error.path, error.line))
        return f"{where}: {problem}"
    if isinstance(error, GeomexactError):
        return f"{name}: {without_file_text(without_prefixes(str(error), prefixes), None)}"
    if isinstance(error, OSError):
        return f"{name}: cannot read it ({error.strerror or type(error).__name__})"
    return f"{name}: cannot be read ({type(error).__name__}; the reader's message is not shown)"
