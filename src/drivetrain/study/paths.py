"""Paths into an axis-file mapping: ``mechanism.load.mass``, ``profile[0].time``, ``transmission[1].ratio``.

A path names keys (after dots) and list positions (in brackets). Setting a value copies only the
mappings and lists along the path, so thousands of variants of one base share the rest.
"""

from __future__ import annotations

import re
from typing import Any

from drivetrain.errors import InputError

_TOKEN = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]")

Token = str | int


def parse_path(path: str, field: str) -> tuple[Token, ...]:
    """``'profile[0].time'`` -> ``('profile', 0, 'time')``; InputError naming ``field`` if malformed."""
    tokens: list[Token] = []
    pos = 0
    text = path.strip()
    while pos < len(text):
        if text[pos] == "." and tokens and pos + 1 < len(text) and text[pos + 1] != ".":
            pos += 1
        m = _TOKEN.match(text, pos)
        if m is None:
            raise InputError(field, "is not a path such as mechanism.load.mass or profile[0].time", path)
        tokens.append(m.group(1) if m.group(1) is not None else int(m.group(2)))
        pos = m.end()
    if not tokens or not isinstance(tokens[0], str):
        raise InputError(field, "is not a path such as mechanism.load.mass or profile[0].time", path)
    return tuple(tokens)


def get_path(data: Any, tokens: tuple[Token, ...]) -> tuple[bool, Any]:
    """(found, value) at ``tokens`` in nested mappings and lists."""
    node = data
    for t in tokens:
        in_list = isinstance(t, int) and isinstance(node, list) and 0 <= t < len(node)
        in_map = isinstance(t, str) and isinstance(node, dict) and t in node
        if in_list or in_map:
            node = node[t]
        else:
            return False, None
    return True, node


def set_path(data: Any, tokens: tuple[Token, ...], value: Any, field: str = "") -> Any:
    """A copy of ``data`` with ``value`` at ``tokens``; missing mappings on the way are created.

    A list position that does not exist is an InputError naming ``field`` (a variant cannot add
    a profile step or a stage).
    """
    if not tokens:
        return value
    head, rest = tokens[0], tokens[1:]
    if isinstance(head, int):
        if not isinstance(data, list) or not 0 <= head < len(data):
            n = len(data) if isinstance(data, list) else 0
            raise InputError(field, f"position [{head}] does not exist in the base axis file (it has {n})",
                             has_value=False)
        out_l = list(data)
        out_l[head] = set_path(data[head], rest, value, field)
        return out_l
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise InputError(field, f"{head!r} cannot be set: the base axis file has a value, not a mapping, there",
                         has_value=False)
    out = dict(data)
    out[head] = set_path(data.get(head), rest, value, field)
    return out


def get_dotted(data: Any, path: str) -> tuple[bool, Any]:
    """Look up a dotted path (``selection.selected.motor``, ``candidates[0].ok``) in a result mapping."""
    try:
        tokens = parse_path(path, "record")
    except InputError:
        return False, None
    return get_path(data, tokens)


__all__ = ["get_dotted", "get_path", "parse_path", "set_path"]
