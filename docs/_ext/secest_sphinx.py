"""Sphinx extension of the secest site.

* ``{badge}`text``` — a coloured verdict / status badge (``holds``, ``fails``,
  ``[Re, partial]``, ``reproduced``, ``ours`` ...).
* Numbered, captioned figures on the notebook pages (``papers/<key>``,
  ``beyond/<key>``). Each figure a notebook saves is displayed inline with output
  metadata ``{"secest": {"figure": "<stem>"}}``;
  myst-nb names an image output by the SHA-256 of its bytes, so the extension
  maps those hashes back to the stems (reading the notebook copies) and wraps
  each image in a ``figure`` node captioned from ``figures/manifest.toml``
  (the paper's figure number, title, status, a link to the CSV data), labelled
  ``fig-<key>-<stem>``. The notebooks are not edited for this.
* ``{figref}`fig-<key>-<stem>``` — "Figure 3.4", linked to that numbered figure (the
  gallery uses it). Sphinx's ``{numref}`` reloads the whole target page from disk for
  each reference (53 paper pages for the gallery, 5 s of the build); this role reads
  the number Sphinx assigned (``env.toc_fignumbers``) and the label's page instead.
* Every figure image gets its caption's text as alt text, and every image of a page body
  loads lazily (``loading="lazy"``), so a page reaches its load event without its figures.
* ``_static/secest-icons.css``: the theme's icon classes with the one icon font inline
  (the theme's 1.5 MB icon script is not loaded; ``docs/_templates/static/webpack-macros.html``).
* ``:::{secest-fold} summary`` — a block folded behind its summary line (``<details>``).
* Long prose folded on the notebook pages (:class:`FoldLongProse`): a paragraph of a section
  (not the page's opening) longer than ``FOLD_PROSE_CHARS`` characters shows its first sentences,
  at least ``PROSE_LEAD_CHARS`` characters, and the rest opens with a "more" toggle (a checkbox and
  CSS, no script). The end matter (``END_MATTER``) shows its first paragraph, the rest in a
  ``<details>``; a link to such a section opens it (``_static/secest-fold.js``). The words stay
  in the page (search finds them); the notebooks are not edited.
* After the build, the ``.ipynb`` that the theme's download button serves
  (``_sources/papers/<key>.ipynb``, ``_sources/beyond/<key>.ipynb``) is replaced by the
  committed notebook, so
  the download is byte for byte the file in the repository.
"""

from __future__ import annotations

import base64
import hashlib
import json
import os
import re
import shutil
from pathlib import Path
from typing import Any

from docutils import nodes
from sphinx import addnodes
from sphinx.application import Sphinx
from sphinx.transforms import SphinxTransform
from sphinx.util import logging
from sphinx.util.docutils import SphinxDirective

from secest.repro.site import (
    END_MATTER,
    FOLD_PROSE_CHARS,
    PROSE_LEAD_CHARS,
    ROOT,
    ascii_maths,
    load_manifest,
    sentence_cut,
)

logger = logging.getLogger(__name__)


def _badge_class(text: str) -> str:
    slug = text.lower().replace("¬", "not-")
    slug = re.sub(r"[^a-z0-9]+", "-", slug).strip("-")
    return f"secest-badge-{slug or 'none'}"


def badge_role(name, rawtext, text, lineno, inliner, options=None, content=None):  # noqa: ANN001
    """``{badge}`holds``` -> <span class="secest-badge secest-badge-holds">holds</span>."""
    node = nodes.inline(rawtext, text, classes=["secest-badge", _badge_class(text)])
    return [node], []


class figure_ref(nodes.Inline, nodes.Element):
    """A reference to a numbered figure, replaced by a link once the numbers are known."""


def figref_role(name, rawtext, text, lineno, inliner, options=None, content=None):  # noqa: ANN001
    """``{figref}`fig-lee2020-fig1-theta-sum``` -> "Figure 3.4", linked to the figure."""
    return [figure_ref(rawtext, reftarget=text.strip().lower())], []


def _resolve_figrefs(app: Sphinx, doctree: nodes.document, fromdocname: str) -> None:
    std = app.env.get_domain("std")
    form = app.config.numfig_format["figure"]
    for node in list(doctree.findall(figure_ref)):
        target = node["reftarget"]
        docname, labelid, _ = std.labels.get(target, ("", "", ""))
        number = app.env.toc_fignumbers.get(docname, {}).get("figure", {}).get(labelid)
        if number is None:
            logger.warning("secest: %s names no numbered figure", target, location=node)
            node.replace_self(nodes.Text(target))
            continue
        uri = app.builder.get_relative_uri(fromdocname, docname) + "#" + labelid
        ref = nodes.reference("", "", internal=True, refuri=uri)
        text = form % ".".join(map(str, number))
        ref += nodes.inline(text, text, classes=["std", "std-numref"])
        node.replace_self(ref)


def _figure_index(app: Sphinx) -> dict[str, dict[str, dict[str, Any]]]:
    """docname -> image hash -> figure info, from the notebook copies and the manifest."""
    manifest = load_manifest(ROOT)
    index: dict[str, dict[str, dict[str, Any]]] = {}
    for path in sorted([*Path(app.srcdir, "papers").glob("*.ipynb"),
                        *Path(app.srcdir, "beyond").glob("*.ipynb")]):
        key = path.stem
        listed = {}
        for fig in manifest.get(key, {}).get("figures", []):
            for f in fig.get("files", []):
                if f.endswith(".png"):
                    listed[Path(f).stem] = fig
        hashes: dict[str, dict[str, Any]] = {}
        nb = json.loads(path.read_text())
        for cell in nb["cells"]:
            for out in cell.get("outputs", []):
                stem = out.get("metadata", {}).get("secest", {}).get("figure")
                data = out.get("data", {}).get("image/png")
                if not stem or not data:
                    continue
                raw = base64.b64decode("".join(data) if isinstance(data, list) else data)
                digest = hashlib.sha256(raw).hexdigest()
                hashes[digest] = {"key": key, "stem": stem, "manifest": listed.get(stem)}
        index[f"{path.parent.name}/{key}"] = hashes
    return index


def _caption_text(key: str, stem: str, fig: dict[str, Any] | None) -> tuple[str, str]:
    if fig is None:
        return f"{stem} (not listed in figures/manifest.toml)", "unlisted"
    paper = str(fig.get("paper", ""))
    title = str(fig.get("title", stem))
    if paper.lower().startswith("none"):
        where = paper[4:].strip(" ()")
        origin = f"Ours, not in the paper ({where})" if where else "Ours, not in the paper"
    else:
        origin = f"Paper's {paper}"
    return f"{origin}: {title}.", str(fig.get("status", "?"))


def typeset_nodes(text: str) -> list[nodes.Node]:
    """Text with ``<sub>``/``<sup>`` tags (:func:`secest.repro.site.ascii_maths`) as docutils nodes."""
    root = nodes.inline()
    stack: list[nodes.Element] = [root]
    for piece in re.split(r"(</?su[bp]>)", text):
        if piece in ("<sub>", "<sup>"):
            node = nodes.subscript() if piece == "<sub>" else nodes.superscript()
            stack[-1] += node
            stack.append(node)
        elif piece in ("</sub>", "</sup>"):
            if len(stack) > 1:
                stack.pop()
        elif piece:
            stack[-1] += nodes.Text(piece)
    children = list(root.children)
    root.children = []
    return children


def plain_alt(text: str) -> str:
    """Alt text from typeset text: ``P<sub>k</sub>`` -> ``P_k``, ``x<sup>2</sup>`` -> ``x^2``."""
    return re.sub(r"</su[bp]>", "", text.replace("<sub>", "_").replace("<sup>", "^"))


class NumberNotebookFigures(SphinxTransform):
    """Wrap each saved-figure image output of a paper page in a numbered, captioned figure."""

    default_priority = 400

    def apply(self, **kwargs: Any) -> None:
        docname = self.env.docname
        hashes = self.env.app.secest_figures.get(docname)  # type: ignore[attr-defined]
        if not hashes:
            return
        self.env.note_dependency(str(ROOT / "figures" / "manifest.toml"))  # captions come from it
        seen: set[str] = set()
        for bundle in list(self.document.findall(nodes.container)):
            if bundle.get("nb_element") != "mime_bundle" or isinstance(bundle.parent, nodes.figure):
                continue
            info = None
            for image in bundle.findall(nodes.image):
                digest = Path(image["uri"]).stem
                info = hashes.get(digest)
                if info:
                    break
            if info is None:
                continue
            key, stem = info["key"], info["stem"]
            if stem in seen:
                continue
            seen.add(stem)
            text, status = _caption_text(key, stem, info["manifest"])
            text = ascii_maths(text)  # "tr Gamma+" -> "tr Γ⁺", "P_{k}" -> P with a subscript
            for image in bundle.findall(nodes.image):  # alt text: what the figure shows
                image["alt"] = plain_alt(text)
            figure = nodes.figure(classes=["secest-figure"])
            figure["names"].append(f"fig-{key}-{stem}".lower())
            bundle.replace_self(figure)
            figure += bundle
            caption = nodes.caption("", "")
            caption.extend(typeset_nodes(text + " "))
            caption += nodes.inline(status, status, classes=["secest-badge", _badge_class(status)])
            csv = ROOT / "figures" / key / f"{stem}.csv"
            if csv.is_file():
                caption += nodes.Text(" Data: ")
                target = os.path.relpath(csv, Path(self.env.srcdir, docname).parent)
                ref = addnodes.download_reference(
                    "", "", refdoc=docname, reftarget=target, refexplicit=True, refwarn=False
                )
                ref += nodes.literal(csv.name, csv.name, classes=["xref", "download"])
                caption += ref
                caption += nodes.Text(".")
            figure += caption
            self.document.note_explicit_target(figure, figure)
        missing = {h["stem"] for h in hashes.values()} - seen
        for stem in sorted(missing):
            logger.warning(
                "secest: figure %s of %s found in the notebook but not rendered",
                stem,
                docname,
                location=docname,
            )


class fold_toggle(nodes.Inline, nodes.Element):
    """The "more" toggle of a folded paragraph: a checkbox and its label (HTML only)."""


class fold_rest(nodes.Inline, nodes.TextElement):
    """The folded rest of a paragraph, shown when its toggle is checked."""


class section_fold(nodes.General, nodes.Element):
    """The folded rest of an end-matter section (HTML ``<details>``)."""


def _fold_end_matter(section: nodes.section) -> None:
    """Fold an end-matter section (:data:`~secest.repro.site.END_MATTER`) after its first
    paragraph: its title and that paragraph stay in view, the rest opens on a click."""
    depth = sum(isinstance(a, nodes.section) for a in _ancestors(section))
    title = section.next_node(nodes.title)
    if depth != 1 or title is None or title.astext().strip() not in END_MATTER:
        return
    keep = 2 if len(section.children) > 1 and isinstance(section.children[1], nodes.paragraph) else 1
    rest = section.children[keep:]
    if not rest:
        return
    del section.children[keep:]
    box = section_fold("", summary=f"The rest of this section: {_contents(rest)}")
    box.extend(rest)
    section += box


class FoldDirective(SphinxDirective):
    """``:::{secest-fold} summary`` — its content folded behind the summary line."""

    has_content = True
    required_arguments = 1
    final_argument_whitespace = True

    def run(self) -> list[nodes.Node]:
        box = section_fold("", summary=self.arguments[0])
        self.state.nested_parse(self.content, self.content_offset, box)
        return [box]


def _contents(block: list[nodes.Node]) -> str:
    """What a folded block holds, in words: "4 paragraphs, 2 code cells, a table"."""
    counts = {"paragraph": 0, "list": 0, "code cell": 0, "table": 0, "equation": 0}
    for top in block:
        for node in top.findall(include_self=True):
            if isinstance(node, nodes.container) and "cell" in node.get("classes", []):
                counts["code cell"] += 1
            elif isinstance(node, nodes.paragraph) and not _in(node, (nodes.container, nodes.table,
                                                                       nodes.list_item)):
                counts["paragraph"] += 1
            elif isinstance(node, (nodes.bullet_list, nodes.enumerated_list)) and not _in(
                    node, (nodes.container, nodes.list_item)):
                counts["list"] += 1
            elif isinstance(node, nodes.table) and not _in(node, (nodes.container,)):
                counts["table"] += 1
            elif isinstance(node, nodes.math_block):
                counts["equation"] += 1
    parts = [f"{n} {word}{'s' if n > 1 else ''}" for word, n in counts.items() if n]
    return ", ".join(parts) or "more"


def _in(node: nodes.Node, kinds: tuple[type, ...]) -> bool:
    return any(isinstance(a, kinds) for a in _ancestors(node))


_NO_FOLD = (section_fold, nodes.Admonition, nodes.caption, nodes.footnote, nodes.container,
            nodes.field_list, nodes.topic, nodes.sidebar, nodes.title)


class FoldLongProse(SphinxTransform):
    """Fold the long paragraphs of a notebook page's sections after their first sentences.

    A paragraph of a section, a list item or a table cell (the paragraphs of the page's
    opening, before its first section, are left whole), outside admonitions, captions, notebook
    cells and folded end matter, whose text is longer
    than :data:`~secest.repro.site.FOLD_PROSE_CHARS` characters is cut at the first sentence
    end past :data:`~secest.repro.site.PROSE_LEAD_CHARS` characters
    (:func:`~secest.repro.site.sentence_cut`); the nodes after the cut move into a
    :class:`fold_rest`, hidden until its :class:`fold_toggle` is checked.
    """

    default_priority = 410

    def apply(self, **kwargs: Any) -> None:
        if not self.env.docname.startswith(("papers/", "beyond/")):
            return
        for section in list(self.document.findall(nodes.section)):
            _fold_end_matter(section)
        for n, para in enumerate(list(self.document.findall(nodes.paragraph))):
            if self._foldable(para):
                self._fold(para, f"secest-more-{n}")

    @staticmethod
    def _foldable(para: nodes.paragraph) -> bool:
        depth, in_item = 0, False
        for anc in _ancestors(para):
            if isinstance(anc, _NO_FOLD):
                return False
            depth += isinstance(anc, nodes.section)
            in_item = in_item or isinstance(anc, (nodes.list_item, nodes.entry))
        return (depth >= 2 or in_item) and len(para.astext()) > FOLD_PROSE_CHARS

    @staticmethod
    def _fold(para: nodes.paragraph, ident: str) -> None:
        seen = 0
        for i, child in enumerate(para.children):
            if isinstance(child, nodes.Text):
                cut = sentence_cut(str(child), max(PROSE_LEAD_CHARS - seen, 0))
                if cut is not None and len(para.astext()) - seen - cut >= FOLD_MIN_REST:
                    text = str(child)
                    rest = [nodes.Text(text[cut:]), *para.children[i + 1:]]
                    del para.children[i:]
                    para += nodes.Text(text[:cut])
                    words = len("".join(r.astext() for r in rest).split())
                    para += fold_toggle("", ident=ident, words=words)
                    box = fold_rest("", "", ident=ident)
                    box.extend(rest)
                    para += box
                    return
            seen += len(child.astext())


FOLD_MIN_REST = 80
"""A paragraph's rest shorter than this many characters is not folded (a toggle for a few words
would cost the reader more than it saves)."""


def _ancestors(node: nodes.Node) -> Any:
    parent = node.parent
    while parent is not None:
        yield parent
        parent = parent.parent


def _visit_toggle(self: Any, node: fold_toggle) -> None:
    ident = node["ident"]
    self.body.append(
        f'<input type="checkbox" class="secest-more-toggle" id="{ident}">'
        f'<label class="secest-more-open" for="{ident}">… more ({node["words"]} words)</label>'
    )
    raise nodes.SkipNode


def _visit_rest(self: Any, node: fold_rest) -> None:
    self.body.append('<span class="secest-more-rest">')


def _depart_rest(self: Any, node: fold_rest) -> None:
    self.body.append(f' <label class="secest-more-close" for="{node["ident"]}">less</label></span>')


def _visit_section_fold(self: Any, node: section_fold) -> None:
    summary = self.encode(node["summary"])
    self.body.append(f'<details class="secest-section-more"><summary>{summary}</summary>')


def _depart_section_fold(self: Any, node: section_fold) -> None:
    self.body.append("</details>")


def _skip(self: Any, node: nodes.Node) -> None:
    raise nodes.SkipNode


def _builder_inited(app: Sphinx) -> None:
    app.secest_figures = _figure_index(app)  # type: ignore[attr-defined]


def _replace_sources(app: Sphinx, exc: Exception | None) -> None:
    """Serve the committed notebooks (not the copies with a header cell) as downloads."""
    if exc is not None or app.builder.format != "html":
        return
    for folder in ("papers", "beyond"):
        for path in Path(app.srcdir, folder).glob("*.ipynb"):
            target = Path(app.outdir, "_sources", folder, path.name)
            if target.parent.is_dir():
                shutil.copyfile(ROOT / "notebooks" / path.name, target)


_EAGER_IMG = re.compile(r"<img (?![^>]*\bloading=)")


def _lazy_images(app: Sphinx, pagename: str, templatename: str, context: dict, doctree: Any) -> None:
    """Images load when they come near the view (``loading="lazy"``), not before the load event."""
    if "body" in context:
        context["body"] = _EAGER_IMG.sub('<img loading="lazy" decoding="async" ', context["body"])


ICONS_CSS = "secest-icons.css"


def _icon_css(app: Sphinx, exc: Exception | None) -> None:
    """``_static/secest-icons.css``: the theme's Font Awesome classes with its solid font inline.

    The theme draws its icons with Font Awesome's 1.5 MB ``all.min.js``, or with web fonts that a
    page opened from disk (``file://``) may not load (fonts are fetched in CORS mode). This
    stylesheet keeps the icon classes of ``css/all.min.css``, drops its ``@font-face`` rules and
    declares the one font the site's icons use, the solid style, as a ``data:`` URL (156 kB).
    """
    if exc is not None or app.builder.format != "html":
        return
    vendor = Path(app.outdir, "_static", "vendor", "fontawesome", "6.5.2")
    css = re.sub(r"@font-face\{[^}]*\}", "", (vendor / "css" / "all.min.css").read_text())
    font = base64.b64encode((vendor / "webfonts" / "fa-solid-900.woff2").read_bytes()).decode()
    face = (
        '@font-face{font-display:block;font-family:"Font Awesome 6 Free";font-style:normal;'
        f'font-weight:900;src:url(data:font/woff2;base64,{font}) format("woff2")}}'
    )
    Path(app.outdir, "_static", ICONS_CSS).write_text(face + "\n" + css)


def setup(app: Sphinx) -> dict[str, Any]:
    app.add_role("badge", badge_role)
    app.add_role("figref", figref_role)
    app.add_node(figure_ref)
    app.connect("doctree-resolved", _resolve_figrefs)
    app.add_transform(NumberNotebookFigures)
    app.add_node(fold_toggle, html=(_visit_toggle, None), latex=(_skip, None), text=(_skip, None))
    app.add_node(fold_rest, html=(_visit_rest, _depart_rest))
    app.add_node(section_fold, html=(_visit_section_fold, _depart_section_fold))
    app.add_transform(FoldLongProse)
    app.add_directive("secest-fold", FoldDirective)
    app.connect("builder-inited", _builder_inited)
    app.connect("build-finished", _replace_sources)
    app.connect("html-page-context", _lazy_images)
    app.connect("build-finished", _icon_css)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
