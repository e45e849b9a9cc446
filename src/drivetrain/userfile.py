"""Reading a file a user names: one function for every input file (axis, machine, study, catalog import).

A path given by a user may name anything: a device that never ends (``/dev/zero``), a FIFO that
never answers, a directory, a path with a NUL byte in it, or a file far larger than any input. Each
is refused here, at the field that named it, before a byte is read into memory; a regular file is
read to at most its documented size (``limit``) even if it grows while it is read. The caller
gets the bytes or the text, or an ``InputError`` naming the field, the path and the rule.

No command-line dependency: the web app and the Python API use the same functions.
"""

from __future__ import annotations

import os
import stat

from drivetrain.errors import InputError

MAX_PATH_CHARS = 4096
"""Longest path accepted [characters] (Linux's PATH_MAX)."""
_CHUNK = 1 << 20


def check_path(path: str | os.PathLike[str], field: str) -> str:
    """The path as text, or an InputError at ``field`` for one no file can have (NUL byte, too long)."""
    try:
        text = os.fspath(path)
    except TypeError:
        raise InputError(field, "must be the path of a file", type(path).__name__) from None
    if not isinstance(text, str):
        raise InputError(field, "must be the path of a file", type(text).__name__)
    if not text:
        raise InputError(field, "is empty: give the path of a file", has_value=False)
    if "\x00" in text:
        raise InputError(field, "contains a NUL byte, which no file name can hold", text)
    if len(text) > MAX_PATH_CHARS:
        raise InputError(field, f"is longer than {MAX_PATH_CHARS} characters: no file name is",
                         text[:60] + "...")
    return text


def read_bytes(path: str | os.PathLike[str], field: str, limit: int, what: str = "file") -> bytes:
    """The bytes of the regular file at ``path``, at most ``limit`` of them.

    Refused with an InputError at ``field``: a path no file can have, a missing or unreadable file,
    a directory, a device, FIFO or socket (opened without blocking, then judged by ``fstat``), and a
    file of more than ``limit`` bytes (by its size, and by what is read, for a file that grows or
    reports no size, e.g. under /proc). ``what`` names the kind of file in the message.
    """
    text = check_path(path, field)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOCTTY", 0)
    try:
        fd = os.open(text, flags)
    except FileNotFoundError:
        raise InputError(field, "cannot be read (no such file)", text) from None
    except IsADirectoryError:
        raise InputError(field, f"is a directory, not {_article(what)}", text) from None
    except OSError as exc:
        raise InputError(field, f"cannot be read ({exc.strerror or exc})", text) from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise InputError(field, f"is a directory, not {_article(what)}", text)
        if not stat.S_ISREG(info.st_mode):
            kind = ("a device" if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode)
                    else "a FIFO (named pipe)" if stat.S_ISFIFO(info.st_mode)
                    else "a socket" if stat.S_ISSOCK(info.st_mode) else "not a regular file")
            raise InputError(field, f"is {kind}, not {_article(what)}: give a regular file", text)
        if info.st_size > limit:
            raise InputError(field, f"is too large ({info.st_size} bytes; {_article(what)} is at most {limit} bytes)",
                             text)
        chunks: list[bytes] = []
        got = 0
        while got <= limit:
            chunk = os.read(fd, min(_CHUNK, limit + 1 - got))
            if not chunk:
                break
            chunks.append(chunk)
            got += len(chunk)
        if got > limit:
            raise InputError(field, f"is too large (over {limit} bytes; {_article(what)} is at most {limit} bytes)",
                             text)
        return b"".join(chunks)
    except OSError as exc:
        raise InputError(field, f"cannot be read ({exc.strerror or exc})", text) from None
    finally:
        os.close(fd)


def read_text(path: str | os.PathLike[str], field: str, limit: int, what: str = "file",
              encoding: str = "utf-8") -> str:
    """``read_bytes`` decoded (``encoding``; "utf-8-sig" drops a byte-order mark), or an InputError at
    ``field`` naming the first byte that is not valid text."""
    data = read_bytes(path, field, limit, what)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise InputError(field, f"is not UTF-8 text (byte {exc.start})", os.fspath(path)) from None


def _article(what: str) -> str:
    return f"an {what}" if what[:1] in "aeiou" else f"a {what}"


__all__ = ["MAX_PATH_CHARS", "check_path", "read_bytes", "read_text"]
