"""Every source the code cites is one a user can find: an entry of docs/references.md (the lecture and its
sections, the readings of the lecture, a public document) or a file of the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "src" / "drivetrain"
REFERENCES = (ROOT / "docs" / "references.md").read_text(encoding="utf-8")
SOURCES = [p for p in sorted(PACKAGE.rglob("*")) if p.suffix in (".py", ".html", ".js", ".css") and p.is_file()]

LECTURE_QUOTE = re.compile(r"\b[Ll]ecture(?:'s)?[,:]?\s+\\?\"([^\"\\]+)\\?\"")
"""``lecture, "Section"`` (also with a colon, and escaped quotes inside a string)."""
REPO_PATH = re.compile(r"(?<![\w/.])((?:docs|tests|examples|bench|scripts|catalog/data)/[\w./-]*\w\."
                       r"(?:md|py|yaml|csv))")
SOURCE_CLAUSE = re.compile(r"\bSources?: (.+?)(?:\n\s*\n|\"\"\"|\Z)", re.DOTALL)
CROSS_REFERENCE = re.compile(r":func:|:data:|``|\bmodule docstring\b|\bas above\b|\bsee\b|\bsection\b",
                             re.IGNORECASE)
UNFINDABLE = ("design.md", "seed/", "lecture notes in")


def _section(title: str) -> str:
    start = REFERENCES.index(f"\n## {title}")
    end = REFERENCES.find("\n## ", start + 1)
    return REFERENCES[start:end if end > 0 else None]


def _keys() -> list[str]:
    """The "cited as" column of every table of documents."""
    keys = []
    for title in ("Books and papers", "Standards", "Vendor documents", "Software documentation"):
        for line in _section(title).splitlines():
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if line.startswith("|") and cells[0] not in ("cited as", "") and not set(cells[0]) <= set("-"):
                keys.append(cells[0])
    return keys


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def _where(path: Path, text: str, pos: int) -> str:
    return f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, pos) + 1}"


def test_the_references_list_documents_and_the_lecture_sections() -> None:
    assert len(_keys()) > 40 and {"THK", "Ellis", "IEC 60034-1", "Modelica"} <= set(_keys())
    assert "Energy Equivalence Principle" in _section("The lecture")


def test_no_citation_of_a_document_users_do_not_have() -> None:
    found = [f"{_where(p, t, m.start())}: {m.group(0)}" for p in SOURCES for t in [_text(p)]
             for m in re.finditer("|".join(re.escape(u) for u in UNFINDABLE), t)]
    assert not found, "cite docs/conventions.md or docs/references.md instead:\n" + "\n".join(found)


def test_every_quoted_lecture_section_is_listed() -> None:
    lecture = _section("The lecture").lower()
    missing = [f"{_where(p, t, m.start())}: {m.group(1)}" for p in SOURCES for t in [_text(p)]
               for m in LECTURE_QUOTE.finditer(t) if " ".join(m.group(1).split()).lower() not in lecture]
    assert not missing, "lecture sections not in docs/references.md:\n" + "\n".join(missing)


def test_every_repository_file_cited_exists() -> None:
    def exists(rel: str) -> bool:
        return (ROOT / rel).exists() or (PACKAGE / rel).exists()

    missing = [f"{_where(p, t, m.start())}: {m.group(1)}" for p in SOURCES for t in [_text(p)]
               for m in REPO_PATH.finditer(t) if not exists(m.group(1))]
    assert not missing, "cited files that do not exist:\n" + "\n".join(missing)


def test_every_source_clause_names_a_reference_a_file_or_the_code() -> None:
    """A ``Source:`` names an entry of docs/references.md (a document, the lecture, ERRATA), a file of the
    repository, or another part of the code that carries the source (``:func:``, "as above", ...)."""
    keys = re.compile("|".join(rf"(?<!\w){re.escape(k)}(?!\w)" for k in [*_keys(), "lecture", "Lecture", "ERRATA"]))
    bad = []
    for path in [p for p in SOURCES if p.suffix == ".py"]:
        text = _text(path)
        for m in SOURCE_CLAUSE.finditer(text):
            clause = m.group(1)
            if clause.startswith(("str", "tuple", "{", "StrArray")):
                continue  # a parameter or a field named source, not a citation
            if keys.search(clause) or REPO_PATH.search(clause) or CROSS_REFERENCE.search(clause):
                continue
            bad.append(f"{_where(path, text, m.start())}: {' '.join(clause.split())[:100]}")
    assert not bad, "sources that name nothing of docs/references.md:\n" + "\n".join(bad)


@pytest.mark.parametrize("key", ["THK", "Copley", "Siemens 1FT7", "Biagiotti"])
def test_a_key_of_the_references_is_cited_in_the_code(key: str) -> None:
    assert any(key in _text(p) for p in SOURCES)
