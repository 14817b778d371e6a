"""Sphinx configuration of the secest site (``make html``).

The source tree is generated: ``python -m secest.repro.site prepare build/site-src``
copies the static pages of ``docs/`` and the committed executed notebooks there
and generates the landing verdict table, the claims matrix, the gallery, the
errata page and the API pages. This file is the configuration directory
(``sphinx-build -c docs build/site-src build/html``); paths below are relative
to ``docs/`` or absolute.

Execution is off (the committed executed notebooks are rendered as they are),
MathJax is served from the site itself (no CDN), and warnings are errors.
"""

from __future__ import annotations

import sys
from pathlib import Path

import sphinx_book_theme  # noqa: F401  (fail early if the site extras are missing)

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
sys.path.insert(0, str(ROOT))

from secest import __version__  # noqa: E402
from secest.repro.site import build_commit, citation, mathjax_dir  # noqa: E402

CITATION = citation(ROOT)  # CITATION.cff: the one place that names the authors and the repository
project = "secest"
author = CITATION["authors"]
copyright = f"{author}, BSD-3-Clause"  # noqa: A001
release = version = __version__
BUILD = build_commit(ROOT)  # the commit this site is built from, on every page's footer

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",  # [source] links in the API pages
    "sphinxcontrib.bibtex",
    "secest_sphinx",
]

exclude_patterns = ["_build", "**.ipynb_checkpoints", "_generated/*.md"]
templates_path = [str(DOCS / "_templates")]  # the theme's asset macros, without the icon JS
root_doc = "index"
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}

# --- MyST / myst-nb: render the committed outputs, never execute --------------------------
nb_execution_mode = "off"
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist", "substitution"]
myst_heading_anchors = 4
myst_dmath_double_inline = True
nb_render_markdown_format = "myst"

# --- figures, equations, citations --------------------------------------------------------
numfig = True
numfig_secnum_depth = 1  # figures numbered per paper page: Figure <page>.<n>
numfig_format = {"figure": "Figure %s", "table": "Table %s", "code-block": "Listing %s"}
bibtex_bibfiles = [str(DOCS / "references.bib")]
bibtex_default_style = "plain"
bibtex_reference_style = "author_year"

# --- API reference (numpydoc docstrings through napoleon) ---------------------------------
viewcode_follow_imported_members = False  # the source of secest's own modules only
autosummary_generate = False
autosummary_imported_members = False
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autodoc_type_aliases = {"ArrayLike": "ArrayLike", "NDArray": "NDArray"}
napoleon_google_docstring = False
napoleon_numpy_docstring = True
napoleon_use_rtype = False
napoleon_use_ivar = True
napoleon_preprocess_types = False

# --- offline MathJax 3 (bundled by sphinx-mathjax-offline, copied into _static/mathjax) ----
# SVG output needs no web fonts, so pages opened from disk (file://) typeset too.
html_static_path = ["_static", str(mathjax_dir())]
mathjax_path = "mathjax/tex-svg.js"
# ui/lazy (shipped with it) typesets an equation when it comes near the view: a paper page holds
# hundreds, and typesetting all of them first held its load event back by seconds.
mathjax3_config = {
    "loader": {"load": ["ui/lazy"]},
    "svg": {"fontCache": "global"},
    "options": {"enableMenu": True},
}

# --- theme ----------------------------------------------------------------------------------
html_theme = "sphinx_book_theme"
html_title = "secest"
html_short_title = "secest"
html_css_files = ["secest.css"]
html_js_files = ["secest-fold.js"]  # a link to a folded section opens it (secest_sphinx.py)
html_favicon = str(DOCS / "_static" / "favicon.svg")
html_last_updated_fmt = None
html_copy_source = True
html_show_sourcelink = False
html_theme_options = {
    "use_download_button": True,
    "use_fullscreen_button": False,
    "home_page_in_toc": True,
    "show_navbar_depth": 1,
    "show_toc_level": 2,
    "toc_title": "On this page",
    "navigation_with_keys": False,
    "extra_footer": (
        "Rendered from the committed executed notebooks; nothing was re-run to build this site. "
        f"Built from commit <code>{BUILD}</code>."
    ),
}
if CITATION.get("repository"):  # the theme's repository button, once CITATION.cff names the URL
    html_theme_options |= {"repository_url": CITATION["repository"], "use_repository_button": True}
html_context = {"default_mode": "light"}

# Types in numpydoc fields become cross-references word by word: a shape such as
# "(runs, K+1, N, n)" makes "K" a reference, ambiguous since two dataclasses of
# secest.methods.guo2023 have an attribute K. Those are not links anyone wants.
suppress_warnings: list[str] = ["ref.python"]
