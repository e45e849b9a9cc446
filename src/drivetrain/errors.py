"""The one error type for bad input: it names the field, the value and the rule it broke."""

from __future__ import annotations

from typing import Any


class InputError(ValueError):
    """Bad user input.

    ``field`` is a dotted path into the axis file (``mechanism.load.mass``,
    ``profile[2].time``); ``rule`` says what was expected; ``value`` is what was given.
    The CLI prints ``str(err)`` and exits with status 2; the web API answers 422 with it.
    """

    def __init__(self, field: str, rule: str, value: Any = None, *, has_value: bool = True) -> None:
        self.field = field
        self.rule = rule
        self.value = value
        self.has_value = has_value and value is not None
        super().__init__(self.message)

    @property
    def message(self) -> str:
        where = f"{_short(_printable(self.field), MAX_FIELD_CHARS)}: " if self.field else ""
        if self.has_value:
            return f"{where}{self.rule}, got {format_value(self.value)}"
        return f"{where}{self.rule}"

    def at(self, prefix: str) -> InputError:
        """Return the same error with ``prefix`` prepended to its field path."""
        if not prefix:
            return self
        sep = "" if self.field.startswith("[") or not self.field else "."
        return InputError(f"{prefix}{sep}{self.field}", self.rule, self.value, has_value=self.has_value)


class InputErrors(InputError):
    """Several input errors at once (e.g. every bad row of a catalog import)."""

    def __init__(self, errors: list[InputError]) -> None:
        self.errors = errors
        first = errors[0] if errors else InputError("", "invalid input", has_value=False)
        super().__init__(first.field, first.rule, first.value, has_value=first.has_value)

    @property
    def message(self) -> str:
        """The first ``MAX_LISTED_ERRORS`` errors, one a line, and how many more there are."""
        shown = [e.message for e in self.errors[:MAX_LISTED_ERRORS]]
        more = len(self.errors) - len(shown)
        if more > 0:
            shown.append(f"... and {more} more error{'s' if more > 1 else ''}")
        return "\n".join(shown)

    def __str__(self) -> str:
        return self.message


MAX_FIELD_CHARS = 200
"""Longest field path printed (a path may hold a key or a column header of the user's)."""
MAX_LISTED_ERRORS = 20
"""Errors of an ``InputErrors`` printed one a line; the rest are counted."""
MAX_LISTED_ITEMS = 5
"""User-given items a message names (``listing``); the rest are counted."""


def listing(items: Any, first: int = MAX_LISTED_ITEMS) -> str:
    """``a, b, c, d, e and 12 more``: the first few of ``items`` (each shortened as ``format_value``
    does) and a count of the rest, so a message stays short however many items the user gave."""
    items = list(items)
    shown = ", ".join(format_value(x) for x in items[:first])
    more = len(items) - first
    return f"{shown} and {more} more" if more > 0 else shown


def _short(text: str, limit: int) -> str:
    return text if len(text) <= limit else f"{text[:limit - 3]}..."


def format_value(value: Any) -> str:
    """Short, readable rendering of a user value for an error message.

    Text that does not print as itself (NUL, control and bidi characters, lone surrogates, edge
    spaces) is shown escaped, so the message can be printed and shows what is really there; an
    integer too long to print is described by its size.
    """
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 3000:
        return f"an integer of about {int(value.bit_length() * 0.30103)} digits"
    if isinstance(value, str):
        value = value[:200]
        text = value if value and value == value.strip() and value.isprintable() else ascii(value)
    else:
        try:
            text = _printable(str(value))
        except ValueError:  # e.g. an object whose text is too long to build
            text = type(value).__name__
    return text if len(text) <= 80 else text[:77] + "..."


def _printable(text: str) -> str:
    """``text`` itself when every character prints, else with the others escaped."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else ascii(c)[1:-1] for c in text)


def write_failure(field: str, exc: Exception, path: Any, what: str = "the file") -> InputError:
    """A store that could not be written (``exc`` from SQLite or the file system) as an input error
    at ``field``: where (``path``) and why, and that the write was rolled back, so ``what`` is as it
    was before."""
    text = str(exc)
    if "readonly" in text or "read-only" in text:
        why = "the file or its folder is read-only"
    elif "full" in text or "No space" in text:
        why = "the disk is full"
    elif "unable to open" in text:
        why = "its folder cannot be written (the journal cannot be created)"
    elif "locked" in text or "busy" in text:
        why = "another process holds it (try again)"
    else:
        why = "the file system refused the write"
    # the path in the rule, whole: it is where to look (a value would be shortened to 80 characters)
    return InputError(field, f"cannot be written: {why} ({text[:200]}); nothing was changed, {what} is as it "
                      f"was: {_short(_printable(str(path)), 4096)}", has_value=False)
