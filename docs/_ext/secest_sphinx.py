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

from secest.repro.site import ROOT, ascii_maths, load_manifest

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
    app.connect("builder-inited", _builder_inited)
    app.connect("build-finished", _replace_sources)
    app.connect("html-page-context", _lazy_images)
    app.connect("build-finished", _icon_css)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
