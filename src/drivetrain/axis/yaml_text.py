"""The axis file's text read into YAML data under bounds: size, nesting depth, number of values,
aliases, number length, duplicate keys (docs/limits.md). One reader for every YAML file a user names
(axis, machine, study) and for the web app's YAML routes.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from drivetrain.errors import InputError

MAX_FILE_BYTES = 1_000_000
"""Largest axis file accepted [bytes]: a real axis is a few kB."""
MAX_ALIASES = 100
"""YAML aliases allowed: enough for shared blocks, far too few for an alias bomb."""
MAX_NODES = 100_000
"""Values a file may expand to, aliases included."""
MAX_DEPTH = 100
"""Deepest nesting of mappings and lists: a real axis file is under 8 levels deep."""
MAX_DIGITS = 400
"""Longest number written in a file [digits]: a float has 17 significant digits."""


def read_yaml(path: str | Path, field: str = "file") -> Any:
    """Read an axis YAML file safely (``read_yaml_text``); an error names ``field`` and the path."""
    return read_yaml_text(path, field)[1]


def read_yaml_text(path: str | Path, field: str = "file") -> tuple[str, Any]:
    """(text, data) of a YAML file: read through ``drivetrain.userfile`` (a regular file of at most
    ``MAX_FILE_BYTES``: no device, FIFO, directory or NUL in the path), then parsed by ``parse_yaml``
    (the data of a text read before comes from ``yaml_cache``: what the loader gave for it then)."""
    from drivetrain.userfile import read_text

    text = read_text(path, field, MAX_FILE_BYTES, "YAML file")
    from drivetrain.axis import yaml_cache

    found, data = yaml_cache.get(text)  # a text read before: its data, without the YAML library
    if not found:
        try:
            data = parse_yaml(text, str(path))
        except InputError as exc:
            if field != "file" and exc.field == "file":
                raise InputError(field, exc.rule, str(path)) from None
            raise
        yaml_cache.put(text, data)
    return text, data


class _Refused(Exception):
    """A bound of ``parse_yaml`` broken while the document is composed (its rule, and its line)."""

    def __init__(self, rule: str, line: int | None) -> None:
        super().__init__(rule)
        self.rule = f"{rule} (line {line})" if line is not None else rule


def parse_yaml(text: str, source: str = "<text>") -> Any:
    """Parse YAML text with the safe loader and the limits of an input file.

    Bounds, each refused as soon as it is passed, while the document is read: ``MAX_FILE_BYTES``,
    ``MAX_DEPTH`` levels of nesting in block or flow style, ``MAX_NODES`` values, ``MAX_ALIASES``
    aliases and ``MAX_NODES`` values once the aliases are expanded, numbers of ``MAX_DIGITS``
    digits; a key given twice in one mapping is refused naming the key and both lines. The parse
    time is thus bounded (under a second for the largest file within the bounds, bench/RESULTS.md).
    """

    if len(text) > MAX_FILE_BYTES or len(text.encode("utf-8", "replace")) > MAX_FILE_BYTES:
        raise InputError("file", f"is too large (an axis file is at most {MAX_FILE_BYTES} bytes)", _src(source))
    try:
        return _parse(text, source, _loader_class())
    except _Escape:  # libyaml refuses a "\ud800" escape: PyYAML's parser reads it, check_text then names the field
        return _parse(text, source, _loader_class(python=True))


class _Escape(Exception):
    """libyaml refused a Unicode escape that PyYAML's own parser reads."""


def _parse(text: str, source: str, loader_class: Any) -> Any:
    import yaml

    try:
        loader = loader_class(text)
    except yaml.YAMLError as exc:  # the reader refuses NUL and other special characters at once
        raise InputError("file", f"is not valid YAML: {str(exc).splitlines()[0]}", _src(source)) from None
    except UnicodeEncodeError:  # the C reader takes UTF-8: a lone surrogate has none
        raise InputError("file", "is not valid YAML: it holds a character that is not valid Unicode "
                         "(a lone surrogate)", _src(source)) from None
    try:
        try:
            node = loader.get_single_node()
        except _Refused as exc:
            raise InputError("file", exc.rule, _src(source)) from None
        except RecursionError:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source)) from None
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
            problem = str(getattr(exc, "problem", None) or str(exc).splitlines()[0])
            if "nesting depth" in problem:  # libyaml's own bound (1000 levels), met while it reads ahead
                raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels){where}",
                                 _src(source)) from None
            if "Unicode character escape" in problem and loader_class is not _loader_class(python=True):
                raise _Escape from None
            raise InputError("file", f"is not valid YAML{where}: {problem}", _src(source)) from None
        if node is None:
            raise InputError("file", "is empty", _src(source))
        _check_graph(node, source)
        try:
            data = loader.construct_document(node)
        except yaml.YAMLError as exc:
            raise InputError("file", f"is not valid YAML: {str(exc)[:200]}", _src(source)) from None
        except (ValueError, OverflowError, RecursionError) as exc:  # e.g. an integer past Python's digit limit
            raise InputError("file", f"holds a value that cannot be read ({str(exc)[:200]})", _src(source)) from None
    finally:
        loader.dispose()
    return data


@functools.cache
def _loader_class(python: bool = False) -> Any:
    """The safe loader, counting while it composes: past ``MAX_DEPTH`` levels, ``MAX_NODES`` values
    or ``MAX_ALIASES`` aliases it stops at once (``_Refused``, with the line).

    The events come from libyaml's parser where PyYAML has it (``CParser``: 5-10 times faster than
    the pure-Python scanner, whose cost also grows with the flow nesting) and from PyYAML's own
    parser otherwise; the document is composed by PyYAML's composer with these counts and built by
    its safe constructor, so the data are those of ``yaml.safe_load``. ``python``: PyYAML's parser
    even where libyaml is installed. Both parsers read tokens
    only as the composer asks for events, so a file nested 20,000 levels deep is refused after
    reading its first hundred levels.
    """
    import yaml
    from yaml.constructor import SafeConstructor
    from yaml.resolver import Resolver

    composer: Any = yaml.composer.Composer

    class Counting(composer):
        _depth = 0
        _nodes = 0
        _aliases = 0

        def _line(self) -> int | None:
            mark = getattr(self.peek_event(), "start_mark", None)
            return None if mark is None else mark.line + 1

        def compose_node(self, parent: Any, index: Any) -> Any:
            if self.check_event(yaml.AliasEvent):
                self._aliases += 1
                if self._aliases > MAX_ALIASES:
                    raise _Refused(f"uses more than {MAX_ALIASES} YAML aliases", self._line())
                return super().compose_node(parent, index)
            self._nodes += 1
            if self._nodes > MAX_NODES:
                raise _Refused(f"holds more than {MAX_NODES} values", self._line())
            if not self.check_event(yaml.MappingStartEvent, yaml.SequenceStartEvent):  # (CParser: no base class)
                return super().compose_node(parent, index)
            if self._depth >= MAX_DEPTH:
                raise _Refused(f"is nested too deeply (over {MAX_DEPTH} levels)", self._line())
            self._depth += 1
            try:
                return super().compose_node(parent, index)
            finally:
                self._depth -= 1

    cparser: Any = None
    if getattr(yaml, "__with_libyaml__", False) and not python:
        cparser = yaml.cyaml.CParser  # type: ignore[attr-defined]
    constructor: Any = SafeConstructor
    resolver: Any = Resolver
    if cparser is not None:
        class CLoader(Counting, cparser, constructor, resolver):
            def __init__(self, stream: str) -> None:
                cparser.__init__(self, stream)
                composer.__init__(self)
                constructor.__init__(self)
                resolver.__init__(self)

        return CLoader

    class Loader(Counting, yaml.SafeLoader):
        pass

    return Loader


def check_text(data: Any, path: str) -> None:
    """Every key and text value must be valid Unicode (a lone surrogate cannot be printed or stored)."""
    if isinstance(data, dict):
        for key, value in data.items():
            sub = f"{path}.{key}" if path else str(key)
            if isinstance(key, str) and not _valid_unicode(key):
                raise InputError(path or "file", "has a key that is not valid Unicode (a lone surrogate)", key)
            if isinstance(key, str) and not key:
                raise InputError(f"{path}.''" if path else "''", "unknown key (the key is empty)", has_value=False)
            check_text(value, sub)
    elif isinstance(data, list):
        for i, value in enumerate(data):
            check_text(value, f"{path}[{i}]")
    elif isinstance(data, str) and not _valid_unicode(data):
        raise InputError(path, "is not valid Unicode text (a lone surrogate)", data)



def _valid_unicode(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _src(source: str | None) -> str | None:
    return None if source is None or source.startswith("<") else source


def _check_graph(root: Any, source: str) -> None:
    """Refuse alias bombs (the values the aliases expand to), long numbers and keys given twice.

    The composer has bounded the depth, the values as written and the aliases; only aliases can
    make the expanded document larger than the file, so the expansion bound names them."""
    import yaml

    seen_ids: dict[int, int] = {}

    def expanded(node: Any, depth: int, path: str) -> int:
        if depth > MAX_DEPTH:
            raise InputError("file", f"is nested too deeply (over {MAX_DEPTH} levels)", _src(source))
        key = id(node)
        if key in seen_ids:
            return seen_ids[key]
        if isinstance(node, yaml.MappingNode):
            _check_keys(node, path)
            n = 1 + sum(expanded(k, depth + 1, path) + expanded(v, depth + 1, _key_path(path, k))
                        for k, v in node.value)
        elif isinstance(node, yaml.SequenceNode):
            n = 1 + sum(expanded(v, depth + 1, f"{path}[{i}]") for i, v in enumerate(node.value))
        else:
            n = 1
            if (isinstance(node, yaml.ScalarNode) and node.tag.endswith((":int", ":float"))
                    and len(node.value) > MAX_DIGITS):
                raise InputError(path or "file", f"is a number of more than {MAX_DIGITS} digits",
                                 node.value[:20] + "...")
        seen_ids[key] = n
        if n > MAX_NODES:
            raise InputError("file", f"expands to more than {MAX_NODES} values through its YAML aliases "
                             "(an alias bomb?)", _src(source))
        return n

    expanded(root, 0, "")


def _check_keys(node: Any, path: str) -> None:
    """A key written twice in one mapping is refused (YAML forbids it; the loader would keep the last)."""
    import yaml

    first: dict[tuple[str, str], int] = {}
    for k, _ in node.value:
        if not isinstance(k, yaml.ScalarNode) or k.tag == "tag:yaml.org,2002:merge":
            continue  # a merge (<<) may be overridden; complex keys are refused by the schema
        line = k.start_mark.line + 1
        if (k.tag, k.value) in first:
            raise InputError(_key_path(path, k), f"is given twice (lines {first[(k.tag, k.value)]} and {line}): "
                             "give each key once", has_value=False)
        first[(k.tag, k.value)] = line


def _key_path(path: str, key: Any) -> str:
    import yaml

    name = str(key.value)[:100] if isinstance(key, yaml.ScalarNode) else "?"
    return f"{path}.{name}" if path else name
