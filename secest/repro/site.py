"""Generate the Sphinx source tree of the site (``make html``) from the repository's own files.

``python -m secest.repro.site prepare build/site-src`` writes a source tree that
``sphinx-build -c docs build/site-src build/html`` renders. Nothing here is a
second copy of a result: every generated page is derived, at build time, from
the one file that holds it, so the site stays true when they change.

=====================  ==========================================================
page                   generated from
=====================  ==========================================================
``index``              ``docs/index.md``; its intro and the two commands come from
                       ``README.md``, its verdict table from README's table of
                       papers (verdict), ``docs/references.bib`` (DOI),
                       ``figures/<key>/claims.json`` (counts) and the manifest
``papers/<key>``       the committed executed ``notebooks/<key>.ipynb``, copied
                       with one header cell added (citation, DOI, downloads) and
                       ``|`` inside maths in table rows read as Jupyter reads it;
                       figures are captioned and numbered by the Sphinx extension
                       ``docs/_ext/secest_sphinx.py`` from the manifest
``beyond/<key>``       the same for the notebooks that reproduce no paper
                       (:data:`BEYOND_KEYS`: the arena), with a header cell of
                       downloads and links instead of the citation
``claims``             every ``figures/<key>/claims.json``
``gallery``            ``figures/manifest.toml``
``errata``             ``ERRATA.md``, links rewritten to the paper pages
``readme``             ``README.md``, links rewritten
``environment``        ``docs/environment.md``, ``environment.lock`` and each
                       notebook's ``parameters`` cell
``architecture``, ...  the other static pages ``docs/*.md``, copied
``api``                the modules of :mod:`secest` (autosummary + napoleon)
=====================  ==========================================================

Files are written only when their content changes, so an unchanged page is not
rebuilt. Links that would not resolve (an ERRATA anchor that names no heading of
its notebook, a claim ``section`` that names no heading) raise :class:`SiteError`.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tomllib
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from secest.core.validation import ValidationError

__all__ = [
    "SiteError",
    "claims_markdown",
    "errata_markdown",
    "format_value",
    "gallery_markdown",
    "load_manifest",
    "mathjax_dir",
    "myst_slug",
    "notebook_headings",
    "beyond_keys",
    "build_commit",
    "citation",
    "claims_table",
    "fold_tags",
    "link_claim_ids",
    "page_claim_label",
    "notebook_keys",
    "page_of",
    "paper_keys",
    "prepare",
    "readme_papers",
    "readme_markdown",
    "verdict_table",
]

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
VERDICT_TAGS = ("[Re]", "[Re, partial]", "[¬Re]")
BEYOND_KEYS = ("arena",)
"""Notebooks that reproduce no paper (the arena): their pages live under ``beyond/``."""
CLAIM_VERDICTS = ("holds", "fails", "undetermined", "fails-premise", "not-checked")
_MD_SPECIAL = re.compile(r"([\\`*_{}\[\]<>#|~$^])")


class SiteError(ValidationError):
    """A source file of the site is inconsistent (a link or anchor would not resolve)."""


# ------------------------------------------------------------------------------------------
# small helpers
# ------------------------------------------------------------------------------------------


def mathjax_dir() -> Path:
    """The folder holding ``mathjax/`` (MathJax 3) shipped by ``sphinx-mathjax-offline``."""
    for entry in sys.path:
        candidate = Path(entry or ".") / "sphinx-mathjax-offline" / "static"
        if (candidate / "mathjax" / "tex-svg.js").is_file():
            return candidate
    raise SiteError(
        "sphinx-mathjax-offline is not installed (it ships the MathJax the site serves offline); "
        "run `make venv`"
    )


def _git(root: Path, *args: str) -> subprocess.CompletedProcess:
    """``git <args>`` in ``root``, output captured as bytes (never raises on a git error)."""
    return subprocess.run(["git", *args], cwd=root, capture_output=True)


def _git_text(root: Path, *args: str) -> str:
    """The stripped output of ``git <args>`` in ``root``, or ``""`` when git fails."""
    done = _git(root, *args)
    return done.stdout.decode().strip() if done.returncode == 0 else ""


def build_commit(root: Path = ROOT) -> str:
    """The commit the site is built from, as ``<short hash> (<date>)``, for every page's footer.

    Parameters
    ----------
    root : Path, optional
        Repository root.

    Returns
    -------
    str
        ``"1a2b3c4 (2026-12-03)"``, with ``" + uncommitted changes"`` when the work tree differs
        from it, or ``"unknown (not a git work tree)"``.
    """
    commit = _git_text(root, "log", "-1", "--format=%h (%cs)")
    if not commit:
        return "unknown (not a git work tree)"
    dirty = _git_text(root, "status", "--porcelain", "--untracked-files=no")
    return commit + (" + uncommitted changes" if dirty else "")


def citation(root: Path = ROOT) -> dict[str, str]:
    """What ``CITATION.cff`` says that the site shows: authors, title, version, repository.

    Parameters
    ----------
    root : Path, optional
        Repository root.

    Returns
    -------
    dict of str to str
        ``authors`` (names joined by ", "), ``title``, ``version`` and ``repository`` (its
        ``repository-code``, ``""`` when the file names none).

    Raises
    ------
    SiteError
        If ``CITATION.cff`` is missing or names no author.
    """
    import yaml

    path = root / "CITATION.cff"
    if not path.is_file():
        raise SiteError(f"CITATION.cff: expected at {path}, found no file")
    cff = yaml.safe_load(path.read_text())
    names = []
    for person in cff.get("authors") or []:
        name = person.get("name") or " ".join(
            p for p in (person.get("given-names"), person.get("family-names")) if p
        )
        if name:
            names.append(str(name))
    if not names:
        raise SiteError("CITATION.cff: expected at least one author with a name, found none")
    return {
        "authors": ", ".join(names),
        "title": str(cff.get("title", "")),
        "version": str(cff.get("version", "")),
        "repository": str(cff.get("repository-code") or ""),
    }


def escape_md(text: str) -> str:
    """Plain text made safe for MyST: markdown punctuation escaped, newlines joined.

    Inline maths ``$...$`` is kept as it is, so a heading such as "the design at work
    ($K\\ne0$)" is typeset on the site as in the notebook.

    Parameters
    ----------
    text : str
        The text to escape.

    Returns
    -------
    str
        The escaped text.
    """
    joined = " ".join(str(text).split())
    parts = re.split(r"(\$[^$]+\$)", joined)
    return "".join(p if i % 2 else _MD_SPECIAL.sub(r"\\\1", p) for i, p in enumerate(parts))


def escape_md_keep_maths(text: str) -> str:
    """Like ``escape_md``, but inline maths ``$...$`` (a notebook heading's) is left to be typeset."""
    parts = re.split(r"((?<!\\)\$[^$]+\$)", " ".join(str(text).split()))
    return "".join(p if i % 2 else escape_md(p) for i, p in enumerate(parts))


_BRACED = r"\{((?:[^{}]|\{[^{}]*\})*)\}"
_SUBSUP = re.compile(
    r"(?<=[^\s_^\\`*<(\[])([_^])(?:" + _BRACED + r"|([A-Za-z0-9\u0370-\u03ff])(?![\w{]))"
)
_GREEK = {
    name: chr(code)
    for name, code in (
        ("alpha", 0x3B1), ("beta", 0x3B2), ("gamma", 0x3B3), ("Gamma", 0x393), ("delta", 0x3B4),
        ("Delta", 0x394), ("epsilon", 0x3B5), ("eta", 0x3B7), ("theta", 0x3B8), ("Theta", 0x398),
        ("kappa", 0x3BA), ("lambda", 0x3BB), ("Lambda", 0x39B), ("mu", 0x3BC), ("nu", 0x3BD),
        ("xi", 0x3BE), ("Xi", 0x39E), ("pi", 0x3C0), ("Pi", 0x3A0), ("rho", 0x3C1),
        ("sigma", 0x3C3), ("Sigma", 0x3A3), ("tau", 0x3C4), ("phi", 0x3C6), ("Phi", 0x3A6),
        ("psi", 0x3C8), ("Psi", 0x3A8), ("omega", 0x3C9), ("Omega", 0x3A9),
    )
}
_GREEK_WORD = re.compile(r"(?<![A-Za-z0-9`])(" + "|".join(_GREEK) + r")(?![A-Za-z0-9`])")
_ASCII_OPS = (("+-", "±"), ("<=", "≤"), (">=", "≥"), ("!=", "≠"), ("sqrt(", "√("))
_ACCENT = re.compile(r"(?<![\w`])([A-Za-z\u0370-\u03ff])_(hat|bar|tilde)(?![A-Za-z0-9])")
_ACCENTS = {"hat": "\u0302", "bar": "\u0304", "tilde": "\u0303"}


def sub_sup(text: str) -> str:
    """Plain-text indices typeset: ``Q_{2i,k}``, ``y_k^{a,i}`` -> HTML ``<sub>``/``<sup>``.

    A braced index (one level of nested braces) or a single letter or digit that ends the word
    is an index when it follows a character that is not a space; ``lemma_seed`` (an index would
    have to end the word) and ``x0_spread`` are left alone. Indices of indices are typeset too.

    Parameters
    ----------
    text : str
        Plain text (no code, no links: protect those before).

    Returns
    -------
    str
        The text with ``<sub>…</sub>`` and ``<sup>…</sup>``.
    """

    def sub(m: re.Match[str]) -> str:
        tag = "sub" if m.group(1) == "_" else "sup"
        inner = m.group(2) if m.group(2) is not None else m.group(3)
        return f"<{tag}>{sub_sup(inner)}</{tag}>"

    return _SUBSUP.sub(sub, text)


def ascii_maths(text: str) -> str:
    """ASCII maths of the claims and captions in Unicode: Greek names, accents, relations, indices.

    ``Pi+_{i,k}`` -> ``Π⁺<sub>i,k</sub>``, ``x_hat_A`` -> ``x̂<sub>A</sub>``, ``<=`` -> ``≤``,
    ``+-2 sqrt(P_bar)`` -> ``±2 √(P̄)``; a Greek name is replaced only as a whole word (``gamma``,
    not ``gamma0_scale``), and nothing inside backticks changes.

    Parameters
    ----------
    text : str
        Plain text, e.g. a claim's ``paper`` or ``check`` or a figure's title.

    Returns
    -------
    str
        The text with Unicode symbols and ``<sub>``/``<sup>`` tags (not yet escaped for MyST).
    """
    parts = re.split(r"(`[^`]*`|\$[^$]+\$)", text)
    for i in range(0, len(parts), 2):
        t = parts[i]
        for old, new in _ASCII_OPS:
            t = t.replace(old, new)
        t = _ACCENT.sub(lambda m: m.group(1) + _ACCENTS[m.group(2)], t)
        t = _GREEK_WORD.sub(lambda m: _GREEK[m.group(1)], t)
        t = re.sub(r"(?<=[A-Za-z\u0370-\u03ff\u0300-\u036f])\+(?=[_\s),;.]|$)", "\u207a", t)
        t = re.sub(r"(?<=[A-Za-z\u0370-\u03ff\u0300-\u036f])-(?=_)", "\u207b", t)
        t = re.sub(r"(?<=[A-Za-z])~(?![A-Za-z0-9])", "\u0303", t)  # x~ -> x̃
        t = re.sub(r"(?<=\S)_(max|min|inf|sup|ij)(?![A-Za-z0-9])", r"<sub>\1</sub>", t)
        t = re.sub(r"(?<=\S)\^(\([^()\s]*\)|-?\d+)", r"<sup>\1</sup>", t)  # x^(1), B^-1
        parts[i] = sub_sup(t)
    return "".join(parts)


def escape_md_typeset(text: str) -> str:
    """:func:`escape_md` of :func:`ascii_maths`: symbols and indices typeset, the rest escaped."""
    pieces = re.split(r"(</?su[bp]>|\$[^$]+\$)", ascii_maths(" ".join(str(text).split())))
    return "".join(p if i % 2 else _MD_SPECIAL.sub(r"\\\1", p) for i, p in enumerate(pieces))


def myst_slug(title: str) -> str:
    """The anchor MyST gives a heading (``myst_heading_anchors``), from its markdown source.

    MyST slugs the heading's text and inline code only (maths is dropped), GitHub
    style: lower case, spaces to ``-``, every other non-word character removed.

    Parameters
    ----------
    title : str
        The heading's markdown source, without the leading ``#``.

    Returns
    -------
    str
        The anchor (not made unique: see :func:`notebook_headings`).
    """
    text = re.sub(r"(?<!\\)\$[^$]*\$", "", title)  # inline maths is not part of the slug
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links: their text
    text = text.replace("`", "").replace("*", "").replace("\\", "")
    text = re.sub(r"(?<!\w)_|_(?!\w)", "", text)  # emphasis underscores, not intraword ones
    return re.sub(r"[^\w\u4e00-\u9fff\- ]", "", text.lower().replace(" ", "-"))


def jupyter_anchor(title: str) -> str:
    """The anchor Jupyter (and nbconvert) gives a heading: its text with spaces as ``-``."""
    return title.strip().replace(" ", "-")


def _write(path: Path, text: str | bytes, written: set[Path]) -> None:
    """Write ``path`` only if its content differs (keeps Sphinx's incremental build)."""
    data = text.encode() if isinstance(text, str) else text
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_bytes() != data:
        path.write_bytes(data)
    written.add(path.resolve())


def _natural(cid: str) -> tuple[Any, ...]:
    """Sort key: C1, C1b, C2, ..., C10, then X1, ..."""
    m = re.match(r"([A-Za-z]+)(\d+)(.*)", cid)
    if not m:
        return (cid, 0, "")
    return (m.group(1) != "C", m.group(1), int(m.group(2)), m.group(3))


# ------------------------------------------------------------------------------------------
# sources: manifest, README, notebooks, bibliography
# ------------------------------------------------------------------------------------------


def load_manifest(root: Path = ROOT) -> dict[str, Any]:
    """``figures/manifest.toml`` as a dict (paper key -> ``notebook``, ``figures``).

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    dict
        The parsed TOML: paper key -> its table.
    """
    return tomllib.loads((root / "figures" / "manifest.toml").read_text())


def paper_keys(root: Path = ROOT) -> list[str]:
    """Paper keys with a committed executed notebook, sorted (the arena is not a paper).

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    list of str
        The stems of ``notebooks/*.ipynb`` not in :data:`BEYOND_KEYS`, sorted.
    """
    return sorted(p.stem for p in (root / "notebooks").glob("*.ipynb") if p.stem not in BEYOND_KEYS)


def beyond_keys(root: Path = ROOT) -> list[str]:
    """Keys of the committed executed notebooks that reproduce no paper (:data:`BEYOND_KEYS`).

    Parameters
    ----------
    root : Path
        Repository root.
    """
    return [k for k in BEYOND_KEYS if (root / "notebooks" / f"{k}.ipynb").exists()]


def notebook_keys(root: Path = ROOT) -> list[str]:
    """Every notebook on the site: the papers', then those beyond them.

    Parameters
    ----------
    root : Path
        Repository root.
    """
    return paper_keys(root) + beyond_keys(root)


def page_of(key: str) -> str:
    """The site page of notebook ``key``, without suffix: ``papers/<key>`` or ``beyond/<key>``.

    Parameters
    ----------
    key : str
        Notebook key.
    """
    return f"beyond/{key}" if key in BEYOND_KEYS else f"papers/{key}"


def _markdown_tables(text: str) -> Iterable[list[list[str]]]:
    rows: list[list[str]] = []
    for line in [*text.splitlines(), ""]:
        if line.startswith("|"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
            rows.append(cells)
        elif rows:
            yield rows
            rows = []


def readme_papers(root: Path = ROOT) -> dict[str, dict[str, str]]:
    """README's table of papers: key -> ``paper`` (markdown), ``verdict`` (tag), ``why``.

    The table is the one whose header has the columns ``key``, ``paper`` and
    ``verdict``; the verdict cell starts with a bold ReScience tag
    (``**[Re, partial]**``) followed by the reason in parentheses.

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    dict of str to dict
        Paper key -> ``{"paper", "verdict", "why"}``; ``verdict`` is ``"not yet"``
        when the cell has no bold tag.

    Raises
    ------
    SiteError
        If ``README.md`` has no such table.
    """
    text = (root / "README.md").read_text()
    for rows in _markdown_tables(text):
        header = [h.lower() for h in rows[0]]
        if {"key", "paper", "verdict"} <= set(header):
            break
    else:
        raise SiteError("README.md has no table with the columns key, paper and verdict")
    col = {name: header.index(name) for name in ("key", "paper", "verdict")}
    out: dict[str, dict[str, str]] = {}
    for row in rows[2:]:
        key = row[col["key"]].strip("` ")
        cell = row[col["verdict"]]
        m = re.match(r"\*\*(\[[^\]]+\])\*\*\s*(.*)$", cell)
        if m:
            tag, why = m.group(1), m.group(2).strip()
        else:
            tag, why = "not yet", re.sub(r"^\*|\*$", "", cell).strip()
        if why.startswith("(") and why.endswith(")"):
            why = why[1:-1]
        out[key] = {"paper": row[col["paper"]], "verdict": tag, "why": why}
    return out


def bibliography(root: Path = ROOT) -> dict[str, dict[str, str]]:
    """``docs/references.bib`` as key -> lower-cased field -> value (no pybtex needed)."""
    text = (root / "docs" / "references.bib").read_text()
    entries: dict[str, dict[str, str]] = {}
    for m in re.finditer(r"@\w+\s*\{\s*([^,\s]+)\s*,(.*?)\n\}", text, flags=re.S):
        fields = dict(
            (k.lower(), v.strip())
            for k, v in re.findall(r"^\s*(\w+)\s*=\s*\{(.*?)\}\s*,?\s*$", m.group(2), flags=re.M)
        )
        entries[m.group(1)] = fields
    return entries


def read_notebook(path: Path) -> dict[str, Any]:
    """A notebook as plain JSON (nbformat 4)."""
    return json.loads(path.read_text())


def _source(cell: Mapping[str, Any]) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def notebook_headings(nb: Mapping[str, Any]) -> list[tuple[int, str, str]]:
    """Markdown headings of a notebook in order: (level, title, MyST anchor), anchors made unique.

    Lines inside fenced code blocks are not headings. A repeated anchor gets a
    suffix ``-1``, ``-2``, ... as MyST gives it.

    Parameters
    ----------
    nb : mapping
        The notebook as plain JSON (nbformat 4, e.g. from :func:`read_notebook`).

    Returns
    -------
    list of (int, str, str)
        Heading level (1 to 6), title (markdown source) and anchor, in order.
    """
    out: list[tuple[int, str, str]] = []
    seen: dict[str, int] = {}
    for cell in nb["cells"]:
        if cell["cell_type"] != "markdown":
            continue
        fence = False
        for line in _source(cell).splitlines():
            if line.lstrip().startswith(("```", "~~~")):
                fence = not fence
            m = None if fence else re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
            if not m:
                continue
            slug = myst_slug(m.group(2))
            if slug in seen:
                seen[slug] += 1
                slug = f"{slug}-{seen[slug]}"
            else:
                seen[slug] = 0
            out.append((len(m.group(1)), m.group(2), slug))
    return out


def section_anchor(headings: list[tuple[int, str, str]], title: str) -> str | None:
    """MyST anchor of the heading whose text, Jupyter anchor or MyST anchor is ``title``."""
    for _, text, slug in headings:
        if title in (text, jupyter_anchor(text), slug) or myst_slug(title) == slug:
            return slug
    return None


def notebook_title(nb: Mapping[str, Any], key: str) -> str:
    """The text after ``<key> —`` in the notebook's first heading (or the whole heading)."""
    heads = notebook_headings(nb)
    if not heads:
        return key
    title = heads[0][1]
    return re.sub(rf"^{re.escape(key)}\s*[—–-]\s*", "", title)


# ------------------------------------------------------------------------------------------
# value formatting for the claims matrix
# ------------------------------------------------------------------------------------------


def format_number(value: float | int) -> str:
    """Short, exact enough: integers as they are, floats to 4 significant digits."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if value == 0:
        return "0"
    return format(value, ".4g")


def _flatten(value: Any, prefix: str = "") -> list[tuple[str, Any]]:
    if isinstance(value, Mapping):
        out: list[tuple[str, Any]] = []
        for k, v in value.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
        return out
    return [(prefix, value)]


def format_value(value: Any, *, limit: int = 6) -> str:
    """A measured value / threshold as one short line of plain text.

    Numbers to 4 significant digits, lists up to ``limit`` entries, mappings as
    ``key: value`` pairs (nested keys joined by ``.``), at most ``limit`` of them,
    then ``… (n more)``.

    Parameters
    ----------
    value : object
        A value of a claims-JSON entry: None, a number, a string, a list or tuple, a
        mapping (nested values are formatted the same way), or anything else (``str``).
    limit : int, optional
        Most entries of a list or mapping shown. Default 6.

    Returns
    -------
    str
        The text; ``—`` for None.
    """
    if value is None:
        return "—"
    if isinstance(value, bool | int | float):
        return format_number(value)
    if isinstance(value, str):
        return value
    if isinstance(value, list | tuple):
        items = [format_value(v, limit=limit) for v in value[:limit]]
        more = f", … ({len(value) - limit} more)" if len(value) > limit else ""
        return "[" + ", ".join(items) + more + "]"
    if isinstance(value, Mapping):
        pairs = _flatten(value)
        shown = [f"{k}: {format_value(v, limit=limit)}" for k, v in pairs[:limit]]
        if len(pairs) > limit:
            shown.append(f"… ({len(pairs) - limit} more)")
        return "; ".join(shown)
    return str(value)


def _headline(entry: Mapping[str, Any]) -> str:
    measured = entry.get("measured")
    key = entry.get("key")
    if key is not None and isinstance(measured, Mapping) and key in measured:
        return f"{key}: {format_value(measured[key])}"
    return format_value(measured)


def _interval(iv: Mapping[str, Any] | None) -> str:
    if not iv:
        return ""
    level = iv.get("level")
    pct = f"{100 * level:g} % " if isinstance(level, int | float) else ""
    return (
        f"{pct}interval [{format_value(iv.get('low'))}, {format_value(iv.get('high'))}]"
        f" ({iv.get('method', '?')})"
    )


# ------------------------------------------------------------------------------------------
# generated pages
# ------------------------------------------------------------------------------------------


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _badge(text: str) -> str:
    return "{badge}`" + text.replace("`", "") + "`"


def _claims(root: Path, key: str) -> dict[str, dict[str, Any]]:
    path = root / "figures" / key / "claims.json"
    return json.loads(path.read_text()) if path.exists() else {}


def _counts(claims: Mapping[str, Mapping[str, Any]]) -> str:
    counts = {v: 0 for v in CLAIM_VERDICTS}
    for entry in claims.values():
        counts[entry.get("verdict", "fails")] = counts.get(entry.get("verdict", "fails"), 0) + 1
    words = {
        "holds": "hold",
        "fails": "fail",
        "undetermined": "undetermined",
        "fails-premise": "premise fails",
        "not-checked": "not checked",
    }
    return ", ".join(f"{n} {words.get(v, v)}" for v, n in counts.items() if n)


def verdict_table(root: Path = ROOT) -> str:
    """The landing page's table: paper, verdict tag and reason (README), DOI, claims, figures.

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    str
        A MyST ``list-table``, one row per paper of :func:`paper_keys`.

    Raises
    ------
    SiteError
        If README has no table of papers, or a link in it would not resolve.
    """
    papers = readme_papers(root)
    bib = bibliography(root)
    manifest = load_manifest(root)
    lines = [
        ":::{list-table}",
        ":header-rows: 1",
        ":widths: 36 20 44",
        ":class: secest-verdicts",
        "",
        "* - Paper",
        "  - Verdict",
        "  - Why",
    ]
    for key in paper_keys(root):
        row = papers.get(key, {"paper": key, "verdict": "not yet", "why": "not in README's table"})
        doi = bib.get(key, {}).get("doi")
        doi_md = f"[doi:{doi}](https://doi.org/{doi})" if doi else "DOI not in the paper text"
        claims = _claims(root, key)
        n_fig = len(manifest.get(key, {}).get("figures", []))
        lines += [
            f"* - [**{key}**](papers/{key}.ipynb): {_rewrite_links(row['paper'], root, Path('.'))}"
            f" {{cite:p}}`{key}`. {doi_md}",
            f"  - {_badge(row['verdict'])}",
            "",
            f"    {{ref}}`{len(claims)} claims <claims-{key}>`: {_counts(claims) or 'none yet'}",
            "",
            f"    {{ref}}`{n_fig} figures <gallery-{key}>`",
            f"  - {_capital(_rewrite_links(row['why'], root, Path('.')))}",
        ]
    lines.append(":::")
    return "\n".join(lines) + "\n"


def readme_intro(root: Path = ROOT) -> tuple[str, str]:
    """README's opening paragraphs (before the first ``##``) and its two-command block."""
    text = (root / "README.md").read_text()
    body = text.split("\n", 1)[1] if text.startswith("# ") else text
    intro = body.split("\n## ", 1)[0].strip()
    m = re.search(r"```bash\n(make figures.*?\nmake test.*?)\n```", text, flags=re.S)
    if not m:
        raise SiteError("README.md has no ```bash block with `make figures` and `make test`")
    return _rewrite_links(intro, root, Path(".")), m.group(1)


def _rel(root: Path, docdir: Path) -> str:
    """Path from a page in ``docdir`` (relative to the source tree) to the repository root."""
    depth = len(docdir.parts)
    return "/".join([".."] * (depth + 2))  # source tree is build/site-src: two levels below root


_LINK = re.compile(r"(?<!!)\[([^\]]+)\]\(([^)\s]+)\)")


def _rewrite_links(text: str, root: Path, docdir: Path) -> str:
    """Rewrite README / ERRATA links from repository paths to site pages or downloads."""
    up = "../" * len(docdir.parts)
    repo = _rel(root, docdir)

    def sub(m: re.Match[str]) -> str:
        label, target = m.group(1), m.group(2)
        if re.match(r"^[a-z]+:", target) or target.startswith("#"):
            return m.group(0)
        path, _, frag = target.partition("#")
        nb = re.fullmatch(r"notebooks/(\w+)\.ipynb", path)
        if nb:
            key = nb.group(1)
            if not (root / path).exists():
                raise SiteError(f"link to {target}: no such notebook")
            if frag:
                anchor = section_anchor(notebook_headings(read_notebook(root / path)), frag)
                if anchor is None:
                    raise SiteError(f"link to {target}: notebook {key} has no heading {frag!r}")
                return f"[{label}]({up}{page_of(key)}.ipynb#{anchor})"
            return f"[{label}]({up}{page_of(key)}.ipynb)"
        if path.startswith("build/html/"):  # the site itself (README's link to the build)
            page = path.removeprefix("build/html/").removesuffix(".html") or "index"
            suffix = ".ipynb" if page in {page_of(k) for k in notebook_keys(root)} else ".md"
            return f"[{label}]({up}{page}{suffix}{'#' + frag if frag else ''})"
        fig = re.fullmatch(r"figures/(\w+)/?", path)
        if fig and (root / path).is_dir():
            return "{ref}`" + label.replace("`", "") + f" <gallery-{fig.group(1)}>`"
        if path in ("ERRATA.md", "README.md"):
            page = path.lower().replace(".md", ".md")
            return f"[{label}]({up}{page}{'#' + frag if frag else ''})"
        if (root / path).is_file():
            return "{download}`" + label.replace("`", "") + f" <{repo}/{path}>`"
        if (root / path).is_dir():
            return f"{label} (`{path}` in the repository)"
        raise SiteError(f"link to {target!r}: no such file in the repository")

    return _LINK.sub(sub, text)


def readme_markdown(root: Path = ROOT) -> str:
    """README.md with its links pointing at the site's pages and downloads.

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    str
        The page's MyST source, labelled ``readme``, its title replaced by ``README``.

    Raises
    ------
    SiteError
        If a link would not resolve (no such file, notebook or heading).
    """
    text = _rewrite_links((root / "README.md").read_text(), root, Path("."))
    text = re.sub(r"\A# .*", "# README", text)
    return "(readme)=\n" + text


def errata_markdown(root: Path = ROOT) -> str:
    """ERRATA.md, each ``notebooks/<key>.ipynb#Deviations-...`` link sent to the paper page heading.

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    str
        The page's MyST source, labelled ``errata``.

    Raises
    ------
    SiteError
        If a link would not resolve (no such file, notebook or heading).
    """
    text = _rewrite_links((root / "ERRATA.md").read_text(), root, Path("."))
    return "(errata)=\n" + typeset_markdown(text)


_MD_KEEP = re.compile(
    r"(```.*?```|`[^`\n]*`|\$[^$\n]+\$|\[[^\]\n]*\]\([^)\n]*\)|\{[a-z:-]+\}`[^`]*`|<[^>\n]+>"
    r"|\*\*|(?<![^\s(])\*[A-Za-z][^*\n]*?(?<=[A-Za-z.])\*(?![\w*])|^\([\w-]+\)=$)",
    flags=re.S | re.M,
)


def typeset_markdown(text: str) -> str:
    """Plain-text maths in markdown prose typeset (ERRATA.md): indices and a lone ``*``.

    Indices ``_{…}``, ``^{…}``, ``_k`` become ``<sub>``/``<sup>`` (:func:`sub_sup`); a ``*``
    that opens no emphasis (``P̄*``, ``φ*/φ_*``) becomes a superscript ``∗`` instead of
    starting stray italics. Code, maths, links, roles, HTML, ``**`` and emphasis of words
    (``*A second machine*``) are left as they are.

    Parameters
    ----------
    text : str
        MyST markdown.

    Returns
    -------
    str
        The markdown with the plain-text maths typeset.
    """
    parts = _MD_KEEP.split(text)
    for i in range(0, len(parts), 2):
        text_i = re.sub(r"(?<=\S)_\*", "<sub>∗</sub>", parts[i])
        parts[i] = sub_sup(text_i).replace("*", "<sup>∗</sup>")
    return "".join(parts)


CLAIM_COLUMNS = (
    "Claim",
    "The paper states (where)",
    "Our check",
    "Measured vs threshold",
    "Outcome",
)
"""The columns of every claims table on the site (the claims matrix and each notebook page)."""


def claims_table(
    key: str,
    claims: Mapping[str, Mapping[str, Any]],
    heads: list[tuple[int, str, str]],
    *,
    on_page: bool,
) -> list[str]:
    """One claims table (MyST ``list-table``), with the columns :data:`CLAIM_COLUMNS`.

    Parameters
    ----------
    key : str
        Notebook key.
    claims : mapping
        ``figures/<key>/claims.json``: claim id -> entry.
    heads : list of (int, str, str)
        The notebook's headings (:func:`notebook_headings`), to link each claim to its section.
    on_page : bool
        True for the table on the notebook's own page (rows labelled :func:`page_claim_label`,
        links within the page), False for the claims matrix (rows labelled :func:`claim_label`).

    Returns
    -------
    list of str
        The table's lines, claims in natural order (C1, C2, ..., C10, then X1, ...).

    Raises
    ------
    SiteError
        If a claim's ``section`` names no heading of the notebook.
    """
    claims_anchor = section_anchor(heads, "Claims") or section_anchor(heads, "Findings (claims)")
    lines = [
        ":::{list-table}",
        ":header-rows: 1",
        ":widths: 11 25 24 22 18",
        ":class: secest-claims",
        "",
        *[("* - " if i == 0 else "  - ") + name for i, name in enumerate(CLAIM_COLUMNS)],
    ]
    if key in BEYOND_KEYS:
        lines[6] = "  - The finding (ours)"
    for cid in sorted(claims, key=_natural):
        lines += _claim_row(key, cid, claims[cid], heads, claims_anchor, on_page=on_page)
    return lines + [":::"]


def claims_markdown(root: Path = ROOT) -> str:
    """The claims matrix: every claim of every paper, one table per paper.

    Read from every ``figures/<key>/claims.json``; each claim links to the notebook
    section that measures it. The tables are those of the notebook pages (:func:`claims_table`).

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    str
        The page's MyST source, labelled ``claims``, a summary table then one
        section ``claims-<key>`` per paper.

    Raises
    ------
    SiteError
        If a claim's ``section`` names no heading of its notebook.
    """
    out = [
        "(claims)=",
        "# Claims matrix",
        "",
        "Every claim that numbers can check, for every paper, generated from "
        "`figures/<key>/claims.json` (written by the notebooks and asserted by the tests); each "
        "paper page opens with its own table, the same. " + CLAIMS_LEGEND,
        "",
    ]
    summary = [
        ":::{list-table}",
        ":header-rows: 1",
        ":class: secest-claims-summary",
        "",
        "* - Paper",
        "  - Claims",
        "  - Verdicts",
    ]
    sections: list[str] = []
    for key in notebook_keys(root):
        claims = _claims(root, key)
        nb = read_notebook(root / "notebooks" / f"{key}.ipynb")
        heads = notebook_headings(nb)
        claims_anchor = section_anchor(heads, "Claims") or section_anchor(heads, "Findings (claims)")
        summary += [
            f"* - {{ref}}`{key} <claims-{key}>`",
            f"  - {len(claims)}",
            f"  - {_counts(claims) or '—'}",
        ]
        sections += [
            f"(claims-{key})=",
            f"## {key} — {escape_md(notebook_title(nb, key))}",
            "",
        ]
        if not claims:
            sections += ["No claims recorded yet.", ""]
            continue
        repo = _rel(root, Path("."))
        sections += [
            f"{len(claims)} claims: {_counts(claims)}. Measured in the "
            f"[notebook]({page_of(key)}.ipynb#{claims_anchor or ''}); full record: "
            "{download}`claims.json <" + f"{repo}/figures/{key}/claims.json" + ">`.",
            "",
            *claims_table(key, claims, heads, on_page=False),
            "",
        ]
    summary.append(":::")
    return "\n".join(out + summary + [""] + sections)


CLAIMS_LEGEND = (
    "**The paper states** is the paper's claim in its words and where it stands; **Our check** is "
    "what we measure and by which rule; **Measured vs threshold** the value at this run's "
    "parameters (with its interval and run count where it is a Monte Carlo value) and what it is "
    "compared with; **Outcome** whether it holds at this run and the verdict over the declared "
    "space: {badge}`holds`, {badge}`fails`, {badge}`fails-premise` (the theorem's own assumption, "
    "or a precondition of the measurement, does not hold), {badge}`undetermined` (holds in part "
    "of the declared space; the fraction is given) or {badge}`not-checked`. Ids `C…` are the "
    "paper's claims, `X…` ours; each links to the section that measures it. Values of many "
    "entries are abbreviated; the full record is each paper's `claims.json`."
)

_BASIS_WORDS = {
    "measured": "measured",
    "by-construction": "true by construction: not evidence",
    "replicate": "a replicate of another claim's measurement: not counted twice",
}


def _claim_row(
    key: str,
    cid: str,
    entry: Mapping[str, Any],
    heads: list[tuple[int, str, str]],
    claims_anchor: str | None,
    *,
    on_page: bool = False,
) -> list[str]:
    """The five cells of one claim (:data:`CLAIM_COLUMNS`); optional keys are shown if present.

    ``basis``, ``runs``, ``decides``, ``interval``, ``premise`` and ``robustness`` are optional;
    a missing ``section`` links to the notebook's Claims section.
    """
    target = f"{Path(page_of(key)).name}.ipynb" if on_page else f"{page_of(key)}.ipynb"
    section = entry.get("section")
    if section:
        anchor = section_anchor(heads, section)
        if anchor is None:
            raise SiteError(f"{key} claim {cid}: section {section!r} names no heading of the notebook")
    else:
        anchor = claims_anchor or ""
    label = page_claim_label(key, cid) if on_page else claim_label(key, cid)
    first = [f"[**{cid}**]({target}#{anchor})"]
    source = entry.get("source") or "—"
    stated = [
        escape_md_typeset(entry.get("paper", "")),
        f"<span class='secest-source'>source: {escape_md(source)}</span>",
    ]
    check = [escape_md_typeset(entry.get("check", ""))]
    basis = entry.get("basis")
    if basis:
        check.append(f"**basis:** {escape_md(_BASIS_WORDS.get(str(basis), str(basis)))}")
    premise = entry.get("premise")
    if premise:
        state = "holds" if premise.get("holds") else "does not hold"
        check.append(f"**premise** ({state}): {escape_md_typeset(premise.get('statement', ''))}")
    measured = [f"**measured:** {escape_md(_headline(entry))}"]
    iv = _interval(entry.get("interval"))
    if iv:
        measured.append(escape_md(iv))
    if entry.get("runs") is not None:
        measured.append(f"runs: {escape_md(format_value(entry['runs']))}")
    threshold = entry.get("threshold")
    if threshold is not None:
        measured.append(f"**threshold:** {escape_md(format_value(threshold))}")
    outcome = [_badge(entry.get("verdict", "fails"))]
    holds = entry.get("holds")
    if isinstance(holds, bool):
        outcome.append("holds at this run" if holds else "does not hold at this run")
    rob = entry.get("robustness")
    if rob:
        frac = rob.get("fraction_holds")
        if isinstance(frac, int | float):
            outcome.append(f"holds in {100 * frac:.0f} % of the declared space")
        measured.append(_robustness_text(rob))
    decides = entry.get("decides")
    if isinstance(decides, bool):
        outcome.append("decides the verdict" if decides else "does not decide the verdict")
    cells = [first, stated, check, measured, outcome]
    rows = [f"* - ({label})=", ""]
    for i, cell in enumerate(cells):
        rows.append(("    " if i == 0 else "  - ") + "\n\n    ".join(cell))
    return rows


def _robustness_text(rob: Mapping[str, Any]) -> str:
    """The sweep's record of a claim: points, region, interval."""
    text = "**over the declared space**"
    if rob.get("points"):
        text += f" ({escape_md(format_value(rob['points']))} points)"
    if rob.get("region"):
        text += f": {escape_md(format_value(rob['region']))}"
    iv = rob.get("interval")
    if isinstance(iv, Mapping) and {"low", "high"} <= set(iv):
        text += f"; fraction holding: {escape_md(_interval(iv))}"
    elif iv:
        text += f"; interval {escape_md(format_value(iv))}"
    return text


def page_claim_label(key: str, cid: str) -> str:
    """The label (and HTML id) of a claim's row in the table on its notebook's page.

    Parameters
    ----------
    key : str
        Notebook key.
    cid : str
        Claim id, e.g. ``C1_nd``.

    Returns
    -------
    str
        ``<key>-claim-<id>``, lower case, ``_`` as ``-``, e.g. ``guo2023-claim-c1-nd``.
    """
    return f"{key}-claim-{cid.lower().replace('_', '-')}"


def claim_label(key: str, cid: str) -> str:
    """The MyST label (and HTML id) of a claim's row: ``claim-<key>-<id>``, lower case, ``_`` as ``-``.

    Parameters
    ----------
    key : str
        Notebook key.
    cid : str
        Claim id, e.g. ``C1_nd``.

    Returns
    -------
    str
        The label, e.g. ``claim-guo2023-c1-nd`` (Sphinx turns ``_`` into ``-`` in ids).
    """
    return f"claim-{key}-{cid.lower().replace('_', '-')}"


def gallery_markdown(root: Path = ROOT) -> str:
    """The figure gallery: paper figure -> our PNG -> status, from ``figures/manifest.toml``.

    Parameters
    ----------
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    str
        The page's MyST source, labelled ``gallery``, one section ``gallery-<key>``
        per paper.
    """
    manifest = load_manifest(root)
    repo = _rel(root, Path("."))
    out = [
        "(gallery)=",
        "# Figure gallery",
        "",
        "Every figure listed in `figures/manifest.toml`, as a grid of thumbnails: click one to see "
        "the figure in its notebook page. Each card names the paper's figure, what ours shows, its "
        "status ({badge}`reproduced`, {badge}`partial`, {badge}`not reproduced`, or {badge}`ours` "
        "for a figure the paper does not have) and the plotted numbers (CSV).",
        "",
    ]
    for key in notebook_keys(root):
        entry = manifest.get(key, {})
        nb = read_notebook(root / "notebooks" / f"{key}.ipynb")
        out += [
            f"(gallery-{key})=",
            f"## {key} — {escape_md(notebook_title(nb, key))}",
            "",
            f"Notebook page: [{key}]({page_of(key)}.ipynb).",
            "",
            "::::{container} secest-grid",
        ]
        for fig in entry.get("figures", []):
            out += _gallery_card(key, fig, repo, root)
        out += ["::::", ""]
    return "\n".join(out)


def _gallery_card(key: str, fig: Mapping[str, Any], repo: str, root: Path) -> list[str]:
    """One card of the gallery grid: thumbnail (linked to the figure), number, status, title, data."""
    files = fig.get("files", [])
    pngs = [f for f in files if f.endswith(".png")]
    data = [f for f in files if not f.endswith(".png")]
    title = escape_md_typeset(fig.get("title", ""))
    lines = [":::{container} secest-card"]
    if pngs:
        stem = Path(pngs[0]).stem
        fid = "fig-" + re.sub(r"[^a-z0-9]+", "-", f"{key}-{stem}".lower())
        alt = re.sub(r"</su[bp]>", "", ascii_maths(str(fig.get("title", stem))))
        alt = alt.replace("<sub>", "_").replace("<sup>", "^")
        lines += [
            f"```{{image}} {repo}/{pngs[0]}",
            f":alt: {json.dumps(alt, ensure_ascii=False)}",
            f":target: {page_of(key)}.html#{fid}",
            ":class: secest-thumb",
            "```",
            f"{{figref}}`fig-{key}-{stem}` {_badge(fig.get('status', '?'))}",
        ]
    else:
        lines += [f"table (CSV only) {_badge(fig.get('status', '?'))}"]
    lines += ["", f"**{escape_md(fig.get('paper', ''))}**: {title}"]
    links = " · ".join(
        "{download}`" + Path(f).name + f" <{repo}/{f}>`" for f in data if (root / f).is_file()
    )
    if links:
        lines += ["", f"<span class='secest-source'>data: {links}</span>"]
    return lines + [":::"]


def lock_markdown(root: Path = ROOT) -> str:
    """The pinned versions of the packages a reader cares about, read from ``environment.lock``."""
    from packaging.markers import Marker

    env = {"python_full_version": "3.11.0", "python_version": "3.11"}  # the lock is for Python 3.11
    pins: dict[str, str] = {}
    text = (root / "environment.lock").read_text()
    for name, version, marker in re.findall(
        r"^([A-Za-z0-9_.\-]+)==([^\s;\\]+)\s*(?:;\s*([^\\\n]*?))?\s*\\?$", text, flags=re.M
    ):
        if not marker or Marker(marker).evaluate(env):
            pins[name] = version
    groups = {
        "numerics": ["numpy", "scipy", "networkx", "control", "cvxpy", "clarabel", "scs"],
        "notebooks": ["matplotlib", "jupytext", "papermill", "nbformat", "nbconvert", "ipykernel"],
        "site": [
            "sphinx",
            "myst-nb",
            "myst-parser",
            "sphinx-book-theme",
            "sphinxcontrib-bibtex",
            "sphinx-mathjax-offline",
        ],
        "tests": ["pytest", "pytest-xdist", "ruff", "hypothesis", "playwright"],
    }
    lower = {k.lower(): (k, v) for k, v in pins.items()}
    lines = [":::{list-table}", ":header-rows: 1", "", "* - used for", "  - pinned versions"]
    for group, names in groups.items():
        found = [f"{lower[n][0]} {lower[n][1]}" for n in names if n in lower]
        lines += [f"* - {group}", f"  - {', '.join(found) or '—'}"]
    lines += [":::", "", f"{len(pins)} packages are pinned for Python 3.11, each with its hashes."]
    return "\n".join(lines) + "\n"


def parameters_markdown(root: Path = ROOT) -> str:
    """Each notebook's declared parameters with their defaults (from its ``parameters`` cell)."""
    out: list[str] = []
    for key in notebook_keys(root):
        nb = read_notebook(root / "notebooks" / f"{key}.ipynb")
        cell = next(
            (c for c in nb["cells"] if "parameters" in c.get("metadata", {}).get("tags", [])), None
        )
        if cell is None:
            continue
        rows = []
        for line in _source(cell).splitlines():
            m = re.match(r"^([A-Za-z_]\w*)\s*=\s*(.*?)\s*(?:#\s*(.*))?$", line)
            if m:
                rows.append((m.group(1), m.group(2), m.group(3) or ""))
        out += [
            "<details>",
            f"<summary><code>{key}</code>: {len(rows)} parameters</summary>",
            "",
            ":::{list-table}",
            ":header-rows: 1",
            ":widths: 20 30 50",
            ":class: secest-params",
            "",
            "* - name",
            "  - default",
            "  - meaning (from the notebook's parameters cell)",
        ]
        for name, value, comment in rows:
            shown = value if len(value) <= 60 else value[:57] + "…"
            out += [f"* - `{name}`", f"  - {escape_md(shown)}", f"  - {escape_md(comment)}"]
        out += [":::", "", "</details>", ""]
    return "\n".join(out)


def _public_names(path: Path) -> list[tuple[str, str]]:
    """(name, kind) of a module's public objects, in ``__all__`` order, read without importing it.

    ``kind`` is ``function``, ``class`` or ``data``; without ``__all__`` every top-level
    function and class whose name does not start with ``_`` is public.
    """
    import ast

    tree = ast.parse(path.read_text())
    kinds: dict[str, str] = {}
    exported: list[str] | None = None
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            kinds[node.name] = "function"
        elif isinstance(node, ast.ClassDef):
            kinds[node.name] = "class"
        elif isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                if isinstance(target, ast.Name):
                    if target.id == "__all__" and node.value is not None:
                        exported = [ast.literal_eval(elt) for elt in node.value.elts]  # type: ignore[attr-defined]
                    else:
                        kinds.setdefault(target.id, "data")
    if exported is None:
        exported = [n for n, k in kinds.items() if k != "data" and not n.startswith("_")]
    return [(name, kinds.get(name, "data")) for name in exported]


def api_module_markdown(module: str, root: Path = ROOT) -> str:
    """One API page: the module docstring, a summary table, then every public object."""
    source = _module_file(module, root)
    names = [] if source.name == "__init__.py" else _public_names(source)  # a package: its modules
    full = f"secest.{module}"
    lines = [f"# `{full}`", "", "```{eval-rst}", f".. automodule:: {full}", "   :no-members:", ""]
    if names:
        lines += [".. rubric:: Summary", "", ".. autosummary::", "   :nosignatures:", ""]
        lines += [f"   {name}" for name, _ in names]
        lines.append("")
    for name, kind in names:
        if kind == "class":
            lines += [f".. autoclass:: {full}.{name}", "   :members:", "   :show-inheritance:", ""]
        else:
            lines += [f".. auto{kind}:: {full}.{name}", ""]
    lines.append("```")
    return "\n".join(lines) + "\n"


def api_modules(root: Path = ROOT) -> list[str]:
    """The public modules of secest, dotted below ``secest``.

    Parameters
    ----------
    root : Path, optional
        Repository root.

    Returns
    -------
    list of str
        Every ``secest/<name>.py`` and every subpackage ``secest/<pkg>/`` with its modules
        (``"methods"``, ``"methods.ding2020"``, ...), names starting with ``_`` left out, sorted.
    """
    package = root / "secest"
    names = []
    for path in package.rglob("*.py"):
        parts = path.relative_to(package).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if parts and not any(part.startswith("_") for part in parts):
            names.append(".".join(parts))
    return sorted(names)


def _module_file(module: str, root: Path) -> Path:
    """The source file of ``secest.<module>`` (a package's ``__init__.py``)."""
    path = root / "secest" / Path(*module.split("."))
    return path / "__init__.py" if path.is_dir() else path.with_suffix(".py")


def api_markdown(root: Path = ROOT) -> str:
    """The API index: the package docstring and a table of contents of the module pages."""
    lines = [
        "(api)=",
        "# API reference",
        "",
        "The shared module `secest`, documented from its numpydoc docstrings. Each function cites the "
        "equation it implements; notebooks show the code where their derivation reaches it. Each "
        "object's `[source]` link opens its code; all of it: "
        "<a href='../_modules/index.html'>the source of every module</a>.",
        "",
        "```{eval-rst}",
        ".. automodule:: secest",
        "   :no-members:",
        "```",
        "",
        "```{toctree}",
        ":maxdepth: 1",
        ":caption: Modules",
        "",
        *api_modules(root),
        "```",
        "",
    ]
    return "\n".join(lines)


def paper_header_cell(key: str, root: Path = ROOT) -> dict[str, Any]:
    """The markdown cell added under a notebook's title on its page: citation, DOI, downloads."""
    bib = bibliography(root).get(key, {})
    papers = readme_papers(root)
    doi = bib.get("doi")
    repo = _rel(root, Path("papers"))
    verdict = papers.get(key, {}).get("verdict", "not yet")
    doi_md = f"[doi:{doi}](https://doi.org/{doi})" if doi else "DOI not in the paper text we have"
    downloads = [
        "{download}`" + f"{key}.ipynb <{repo}/notebooks/{key}.ipynb>` (executed notebook)",
        "{download}`" + f"{key}.py <{repo}/notebooks/{key}.py>` (jupytext source, the one to edit)",
        "{download}`" + f"claims.json <{repo}/figures/{key}/claims.json>`",
    ]
    text = "\n".join(
        [
            ":::{admonition} On this site",
            ":class: secest-paper-box",
            f"**Paper:** {{cite:t}}`{key}`, {doi_md}. **Verdict:** {_badge(verdict)} — see the "
            f"{{ref}}`claims matrix <claims-{key}>`, the {{ref}}`figure gallery <gallery-{key}>` "
            f"and the [errata](../errata.md#{key}).",
            "",
            "**Download:** " + " · ".join(downloads) + "; each figure's data (CSV) is linked "
            "in its caption.",
            "",
            f"This page is the committed executed notebook `notebooks/{key}.ipynb`, rendered without "
            "re-running it. The notebook imports `secest`: to run it, see {ref}`install`; with "
            "other parameters, {ref}`re-running`.",
            ":::",
        ]
    )
    return {"cell_type": "markdown", "metadata": {"tags": ["secest-site"]}, "source": text}


_INLINE_MATH = re.compile(r"(?<![\\$])\$(?![\s$])(.+?)(?<![\s\\])\$(?!\d)")


def _cells(row: str) -> int:
    return len(re.findall(r"(?<!\\)\|", row.strip())) - 1


def protect_table_maths(markdown: str) -> str:
    """Pipes inside ``$...$`` in a markdown table row, as ``\\vert``, where they split the row.

    Jupyter takes the maths out before it parses a table, so ``| $|z|>3$ |`` is one cell
    there; MyST (like GitHub) splits the row at every ``|``. A row is changed only when
    it has more cells than the table's header and the change gives it the header's count.
    """
    lines = markdown.split("\n")
    header: int | None = None
    for i, line in enumerate(lines):
        if not line.lstrip().startswith("|"):
            header = None
            continue
        if header is None:
            header = _cells(line)
            continue
        if _cells(line) > header:
            fixed = _INLINE_MATH.sub(
                lambda m: "$" + re.sub(r"(?<!\\)\|", r"\\vert ", m.group(1)) + "$", line
            )
            if _cells(fixed) == header:
                lines[i] = fixed
    return "\n".join(lines)


def beyond_header_cell(key: str, root: Path = ROOT) -> dict[str, Any]:
    """The markdown cell added under the title of a notebook that reproduces no paper."""
    repo = _rel(root, Path("beyond"))
    downloads = [
        "{download}`" + f"{key}.ipynb <{repo}/notebooks/{key}.ipynb>` (executed notebook)",
        "{download}`" + f"{key}.py <{repo}/notebooks/{key}.py>` (jupytext source, the one to edit)",
        "{download}`" + f"claims.json <{repo}/figures/{key}/claims.json>`",
    ]
    text = "\n".join(
        [
            ":::{admonition} On this site",
            ":class: secest-paper-box",
            "**Beyond the papers:** no paper makes these comparisons; the scenarios, the baselines, "
            f"the scores and the findings are ours. See its {{ref}}`findings <claims-{key}>` in the "
            f"claims matrix and its {{ref}}`figures <gallery-{key}>` in the gallery.",
            "",
            "**Download:** " + " · ".join(downloads) + "; each figure's data (CSV) is linked "
            "in its caption.",
            "",
            f"This page is the committed executed notebook `notebooks/{key}.ipynb`, rendered without "
            "re-running it. The notebook imports `secest`: to run it, see {ref}`install`; with "
            "other parameters, {ref}`re-running`.",
            ":::",
        ]
    )
    return {"cell_type": "markdown", "metadata": {"tags": ["secest-site"]}, "source": text}


LONG_PRINTOUT = 12
"""Plain-text outputs longer than this many lines are folded on the site (:data:`FOLD_RULE`)."""
LISTING_LINES = 24
"""A ``show_source`` listing longer than this many lines scrolls in its own box (the site's CSS,
``docs/_static/secest.css``, says the same: ``max-height: 24lh``)."""
FOLD_PROSE_CHARS = 300
"""A paragraph of a notebook page's sections longer than this many characters is folded after
its first sentences (:data:`FOLD_RULE`; done by the site's Sphinx extension)."""
PROSE_LEAD_CHARS = 140
"""A folded paragraph shows its sentences up to the first sentence end past this many characters."""
END_MATTER = frozenset({
    "Claims", "Verdict", "ReScience verdict", "Deviations from the paper", "Findings (claims)",
    "Deviations and limitations",
})
"""The end matter of a notebook page: a top-level section of one of these titles shows its first
paragraph and folds the rest (:data:`FOLD_RULE`); the page's opening gives the verdict and the
claims table, which these sections derive."""
_SENTENCE_END = re.compile(r"(?<=[.!?])[)\]’”\"']?(?=\s+[A-Z(\[“‘\"0-9])")
_ABBREVIATIONS = frozenset(
    "fig figs sec secs eq eqs thm lem rem def prop ref refs no al e.g i.e cf vs resp approx".split()
)


def sentence_cut(text: str, start: int) -> int | None:
    """Where the first sentence ending at or after ``start`` ends in ``text`` (the index just
    after its full stop), or ``None``.

    A full stop after an abbreviation (``Fig.``, ``Sec.``, ``e.g.``, ``et al.``) or a single
    capital (an initial) does not end a sentence.

    Parameters
    ----------
    text : str
        Plain text (one text node of a paragraph).
    start : int
        The shortest lead, in characters.

    Returns
    -------
    int or None
    """
    for m in _SENTENCE_END.finditer(text, max(start - 1, 0)):
        word = re.search(r"([\w.]+)[.!?][)\]’”\"']?$", text[: m.end()])
        token = (word.group(1) if word else "").lower()
        if token in _ABBREVIATIONS or (word and len(word.group(1)) == 1 and word.group(1).isupper()):
            continue
        if m.end() >= start:
            return m.end()
    return None

FOLD_RULE = (
    "Nothing is removed: the page is the committed notebook. Code: every code cell's input is "
    "folded unless the cell only calls `show_source`, whose output, never folded, is the library's "
    f"own code of the step the derivation has reached (past {LISTING_LINES} lines it scrolls in its "
    "own box). Outputs: the parameter provenance table (`provenance_markdown`), the summary printed "
    "by the cell that writes `claims.json` (`write_claims`; the claims table shows the same) and "
    f"any plain-text printout longer than {LONG_PRINTOUT} lines that is not a `show_source` listing "
    "are folded. Prose: a paragraph of a section, a list item or a table cell longer than "
    f"{FOLD_PROSE_CHARS} characters shows its first sentences (at least {PROSE_LEAD_CHARS} "
    "characters), the rest behind \u201cmore\u201d; the end matter (the sections "
    + ", ".join(f"\u201c{t}\u201d" for t in sorted(END_MATTER)) + ") shows its first paragraph, "
    "the rest behind a click. The paragraphs of the page's opening, captions, equations and figures "
    "are never folded."
)
"""The rule by which the site folds the notebooks' cells (stated on every notebook page)."""


def fold_tags(cell: Mapping[str, Any]) -> list[str]:
    """The myst-nb tags :data:`FOLD_RULE` gives a cell: ``hide-input``, ``hide-output`` or none.

    Parameters
    ----------
    cell : mapping
        A notebook cell (nbformat 4).

    Returns
    -------
    list of str
        The tags to add (an empty list for markdown cells and for cells that only call
        ``show_source``).
    """
    if cell.get("cell_type") != "code":
        return []
    src = _source(cell)
    if _only_show_source(src):
        return []
    tags = ["hide-input"]
    if cell.get("outputs") and (re.search(r"\b(provenance_markdown|write_claims)\(", src)
                                or _long_printout(cell)):
        tags.append("hide-output")
    return tags


def _long_printout(cell: Mapping[str, Any]) -> bool:
    """Whether every output of ``cell`` is plain text (a stream or a text/plain result) and,
    together, longer than :data:`LONG_PRINTOUT` lines."""
    lines = 0
    for out in cell.get("outputs", []):
        if out.get("output_type") == "stream":
            text = out.get("text", "")
        elif out.get("output_type") == "execute_result" and set(out.get("data", {})) == {"text/plain"}:
            text = out["data"]["text/plain"]
        else:
            return False
        lines += len(("".join(text) if isinstance(text, list) else text).splitlines())
    return lines > LONG_PRINTOUT


def _only_show_source(src: str) -> bool:
    """Whether every statement of a code cell is a call of ``show_source`` (the algorithm shown)."""
    import ast

    try:
        body = ast.parse(src).body
    except SyntaxError:  # IPython magics: not a show_source cell
        return False
    return bool(body) and all(
        isinstance(st, ast.Expr)
        and isinstance(st.value, ast.Call)
        and getattr(st.value.func, "id", getattr(st.value.func, "attr", None)) == "show_source"
        for st in body
    )


_PROTECTED = re.compile(
    r"(```.*?```|~~~.*?~~~|`[^`\n]*`|\$\$.*?\$\$|(?<!\\)\$[^$\n]+?\$|\[[^\]\n]*\]\([^)\n]*\)"
    r"|\{[a-z:-]+\}`[^`]*`|<[^>\n]+>|^#{1,6} [^\n]*$|^\([\w-]+\)=$)",
    flags=re.S | re.M,
)


def link_claim_ids(text: str, key: str, ids: Iterable[str]) -> str:
    """Claim ids in a notebook's markdown made links to their rows in the page's claims table.

    Only the prose is changed: code, maths, links, roles, HTML tags, headings (their anchors
    must not move) and targets are left as they are. An id is a whole word equal to a key of
    ``claims.json`` (``C1``, ``C2a``, ``C1_nd``, ``X3``).

    Parameters
    ----------
    text : str
        The markdown source of a cell.
    key : str
        Notebook key.
    ids : iterable of str
        The claim ids of the notebook (keys of its ``claims.json``).

    Returns
    -------
    str
        The text with each id as ``{ref}`C1 <key-claim-c1>```.
    """
    known = sorted(set(ids), key=len, reverse=True)
    if not known:
        return text
    word = re.compile(r"(?<![\w$\\])(" + "|".join(map(re.escape, known)) + r")(?![\w])")
    parts = _PROTECTED.split(text)
    for i in range(0, len(parts), 2):
        parts[i] = word.sub(
            lambda m: "{ref}`" + m.group(1) + " <" + page_claim_label(key, m.group(1)) + ">`", parts[i]
        )
    return "".join(parts)


def claims_table_cell(key: str, nb: Mapping[str, Any], root: Path = ROOT) -> dict[str, Any]:
    """The markdown cell under a notebook page's header: its claims table and the fold rule."""
    claims = _claims(root, key)
    heads = notebook_headings(nb)
    if claims:
        body = [
            f"**Claims at a glance** ({len(claims)}: {_counts(claims)}; the columns are those of "
            f"the {{ref}}`claims matrix <claims>`, each id links to the section that measures it).",
            "",
            *claims_table(key, claims, heads, on_page=True),
        ]
    else:
        body = ["No claims recorded yet."]
    text = "\n".join([*body, "", ":::{secest-fold} How this page is folded", FOLD_RULE, ":::"])
    return {"cell_type": "markdown", "metadata": {"tags": ["secest-site"]}, "source": text}


def paper_notebook(key: str, root: Path = ROOT) -> str:
    """The committed notebook for its page, changed only in how it is shown.

    A header cell and the claims table cell are added after the title cell; code cells get the
    fold tags of :func:`fold_tags`; claim ids in the prose link to the table
    (:func:`link_claim_ids`); maths in table rows is protected as Jupyter does
    (:func:`protect_table_maths`). No cell is removed, no source line of a code cell changes.
    """
    nb = read_notebook(root / "notebooks" / f"{key}.ipynb")
    ids = list(_claims(root, key))
    table = claims_table_cell(key, nb, root)
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            text = _source(cell)
            fixed = link_claim_ids(protect_table_maths(text), key, ids)
            if fixed != text:
                cell["source"] = fixed
        tags = fold_tags(cell)
        if tags:
            meta = cell.setdefault("metadata", {})
            meta["tags"] = [*meta.get("tags", []), *[t for t in tags if t not in meta.get("tags", [])]]
    header = beyond_header_cell if key in BEYOND_KEYS else paper_header_cell
    nb["cells"][1:1] = [header(key, root), table]
    return json.dumps(nb, indent=1, ensure_ascii=False) + "\n"


def source_archive(root: Path = ROOT) -> tuple[str, bytes] | None:
    """The repository's tracked files as the site's source download: ``(file name, tar.gz bytes)``.

    The archive is the build commit (``git archive``); with uncommitted changes to tracked
    files it is a commit object of the work tree made by ``git stash create`` (nothing is
    stashed), so the download is always the code that built the pages. Files unknown to git
    are not in it.

    Parameters
    ----------
    root : Path, optional
        Repository root.

    Returns
    -------
    tuple or None
        ``("secest-<short hash>.tar.gz", data)`` with every path under ``secest-<short hash>/``,
        or None outside a git work tree.
    """
    head = _git_text(root, "rev-parse", "--verify", "HEAD")
    if not head:
        return None
    tree = _git_text(root, "stash", "create") or head
    name = f"secest-{_git_text(root, 'rev-parse', '--short', tree)}"
    done = _git(root, "archive", "--format=tar.gz", f"--prefix={name}/", tree)
    if done.returncode != 0:
        raise SiteError(f"git archive failed: {done.stderr.decode().strip()}")
    return f"{name}.tar.gz", done.stdout


def getcode_markdown(root: Path = ROOT, archive: str | None = None) -> str:
    """How to get the repository: the source download ``archive`` and, if set, ``git clone``.

    Parameters
    ----------
    root : Path, optional
        Repository root.
    archive : str, optional
        File name of :func:`source_archive`'s download in the site's ``_generated`` folder.
    """
    url = citation(root)["repository"]
    commit = build_commit(root)
    text = ""
    if url:
        text += f"```bash\ngit clone {url} secest && cd secest\n```\n\n"
    else:
        text += ("The repository's public address is not recorded in the repository "
                 "(`CITATION.cff` has no `repository-code` yet), so there is no `git clone` line; "
                 "the download below is the repository's content.\n\n")
    if archive:
        stem = archive.removesuffix(".tar.gz")
        text += (
            "**The repository at the commit this site was built from:** "
            "{download}`" + archive + f" </_generated/{archive}>` (every tracked file: code, "
            "notebooks, committed figures, the lock), then\n\n"
            f"```bash\ntar xzf {archive} && cd {stem}\n"
            "make test               # the whole suite; or re-run one paper: make figures NB=lee2020\n"
            "```\n\n"
        )
    return text + f"This site was built from commit `{commit}` (in each page's footer).\n"


def cite_markdown(root: Path = ROOT) -> str:
    """How to cite secest, from ``CITATION.cff`` (authors, title, version) and the build commit."""
    cff = citation(root)
    repo = _rel(root, Path("."))
    where = f", {cff['repository']}" if cff["repository"] else ""
    return (
        f"{escape_md(cff['authors'])}. *{escape_md(cff['title'])}*, version {cff['version']} "
        f"(commit `{build_commit(root)}`){escape_md(where)}.\n\n"
        "The citation metadata, with the five papers as references: "
        "{download}`CITATION.cff <" + f"{repo}/CITATION.cff" + ">` (Citation File Format; "
        "forges and reference managers read it).\n"
    )


def prepare(srcdir: str | Path, root: Path = ROOT) -> list[Path]:
    """Write the site's Sphinx source tree into ``srcdir``; return the files it holds.

    Static pages (``docs/*.md``) are copied, the rest generated. Files in
    ``srcdir`` that this run did not write are removed.

    Parameters
    ----------
    srcdir : str or Path
        The source tree, ``build/<name>`` under ``root`` (``build/site-src`` for
        ``make html``): relative links to repository files assume that depth.
    root : Path, optional
        Repository root; default: the one this package lives in (``secest.repro.site.ROOT``).

    Returns
    -------
    list of Path
        Every file of the source tree, absolute, sorted.

    Raises
    ------
    SiteError
        If ``srcdir`` is not ``build/<name>`` under ``root``, or a generated page
        would hold a link that does not resolve.
    """
    src = Path(srcdir).resolve()
    if src == root.resolve() or root.resolve() not in src.parents:
        raise SiteError(f"srcdir must lie inside the repository (e.g. build/site-src), found {src}")
    if (
        src.relative_to(root.resolve()).parts[:1] != ("build",)
        or len(src.relative_to(root.resolve()).parts) != 2
    ):
        raise SiteError(
            f"srcdir must be build/<name> (links to repository files assume it), found {src}"
        )
    written: set[Path] = set()
    for page in sorted((root / "docs").glob("*.md")):
        _write(src / page.name, page.read_text(), written)
    intro, commands = readme_intro(root)
    gen = src / "_generated"
    _write(gen / "intro.md", intro + "\n", written)
    _write(gen / "commands.md", "```bash\n" + commands + "\n```\n", written)
    _write(gen / "verdicts.md", verdict_table(root), written)
    _write(gen / "lock.md", lock_markdown(root), written)
    _write(gen / "parameters.md", parameters_markdown(root), written)
    from secest.arena.report import card_schema  # the card validator's schema, as tables

    _write(gen / "card_schema.md", card_schema(), written)
    archive = source_archive(root)
    if archive is not None:
        _write(gen / archive[0], archive[1], written)
    _write(gen / "getcode.md", getcode_markdown(root, archive and archive[0]), written)
    _write(gen / "cite.md", cite_markdown(root), written)
    _write(src / "readme.md", readme_markdown(root), written)
    _write(src / "errata.md", errata_markdown(root), written)
    _write(src / "claims.md", claims_markdown(root), written)
    _write(src / "gallery.md", gallery_markdown(root), written)
    _write(src / "api" / "index.md", api_markdown(root), written)
    for module in api_modules(root):
        _write(src / "api" / f"{module}.md", api_module_markdown(module, root), written)
    for key in notebook_keys(root):
        _write(src / f"{page_of(key)}.ipynb", paper_notebook(key, root), written)
    for path in sorted(src.rglob("*"), reverse=True):
        if path.is_file() and path.resolve() not in written:
            path.unlink()
        elif path.is_dir() and not any(path.iterdir()):
            path.rmdir()
    return sorted(written)


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point: ``python -m secest.repro.site prepare [SRCDIR]``.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name: ``prepare`` and optionally the source
        tree (default ``build/site-src``, relative to the repository root).
        Default: ``sys.argv[1:]``.

    Returns
    -------
    int
        0; errors are raised (:class:`SiteError`), argparse exits with status 2 on
        malformed arguments.
    """
    import argparse

    parser = argparse.ArgumentParser(prog="python -m secest.repro.site",
                                     description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("prepare", help="write the Sphinx source tree")
    p.add_argument("srcdir", nargs="?", default="build/site-src")
    args = parser.parse_args(argv)
    if args.command == "prepare":
        files = prepare(ROOT / args.srcdir if not os.path.isabs(args.srcdir) else args.srcdir)
        print(f"secest.repro.site: {len(files)} source files in {args.srcdir}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
