"""The site (`make html`): built with no warning, every link resolves, and a browser shows it.

The module builds the site once, exactly as `make html` does but with a fresh Sphinx
environment (``-E``) so that every warning is reported. The tests that read the HTML
need nothing else; the browser tests drive Debian's Chromium (``/usr/bin/chromium``)
through Playwright, never a browser that Playwright downloads. Without Chromium they
are skipped with a loud reason, unless ``SECEST_REQUIRE_BROWSER=1`` (set by ``.ci/run``),
where they fail. A screenshot of every page is saved under ``build/site-screenshots/`` for
people to look at: what a reader sees on opening it (the first 1280 x 900 px), or the whole
page with ``SECEST_SITE_SHOTS=full`` (``make shots``; a whole paper page is 21 000-26 000 px
tall). Issue #31's checks open every page again at 1280 x 900 and 390 x 844 px: every display
equation whole, no sideways scroll on a phone, menus that open and close, paper pages at most
40 % of their former height and the largest page's load event under 3 s (printed with ``-s``
and written to ``build/site-report.txt``), plus screenshots of each paper page's first two
screens, claims table and a folded / unfolded cell in ``build/site-screenshots/reader/``.
"""

from __future__ import annotations

import html as html_lib
import json
import os
import re
import subprocess
import sys
import tarfile
import tempfile
import threading
import time
from collections.abc import Iterator
from functools import partial
from html.parser import HTMLParser
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urldefrag, urlsplit

import pytest

from secest.repro.results import repo_root
from secest.repro.site import (
    beyond_keys,
    claim_label,
    load_manifest,
    notebook_keys,
    page_of,
    paper_keys,
    readme_papers,
)

ROOT = repo_root()
SRC = ROOT / "build" / "site-src"
HTML = ROOT / "build" / "html"
SHOTS = ROOT / "build" / "site-screenshots"
JPEG_MAX_PX = 60_000  # below JPEG's limit of 65 535 px per side
FULL_PAGE = os.environ.get("SECEST_SITE_SHOTS") == "full"
CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
# what is left in the visible text (code blocks excluded) when maths was not typeset: display or
# inline delimiters, a TeX command, a "$" opening a command, a lone "$" (e.g. a table cell cut
# at a "|" inside $...$), or a $...$ pair
RAW_MATH = re.compile(
    r"\$\$|\\[()\[\]]|\\[A-Za-z]{2,}|\$\\|(?:^|\s)\$(?:\s|$)|(?<![\w$])\$[^$\s][^$\n]*?\$(?![\w$])",
    flags=re.M,
)


# ------------------------------------------------------------------------------------------
# build once, parse the HTML
# ------------------------------------------------------------------------------------------


@pytest.fixture(scope="session")
def site() -> Path:
    """Build the site like `make html` (fresh environment: every warning is reported)."""
    prep = subprocess.run(
        [sys.executable, "-m", "secest.repro.site", "prepare", str(SRC.relative_to(ROOT))],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert prep.returncode == 0, prep.stderr[-4000:]
    build = subprocess.run(
        [sys.executable, "-m", "sphinx", "-E", "-W", "--keep-going", "-q", "-j", "auto", "-b", "html"]
        + ["-c", "docs"]
        + [str(SRC.relative_to(ROOT)), str(HTML.relative_to(ROOT))],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert build.returncode == 0, "sphinx-build -W failed:\n" + build.stderr[-6000:]
    assert "WARNING" not in build.stderr and "ERROR" not in build.stderr, build.stderr[-6000:]
    return HTML


class _Parsed(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: set[str] = set()
        self.links: list[str] = []
        self.assets: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = {k: v or "" for k, v in attrs}
        for key in ("id", "name"):
            if a.get(key) and (key == "id" or tag == "a"):
                self.ids.add(a[key])
        if tag == "a" and "href" in a:
            self.links.append(a["href"])
        elif tag in ("img", "script") and a.get("src"):
            self.assets.append(a["src"])
        elif tag == "link" and a.get("href") and a.get("rel") in ("stylesheet", "preload", "icon"):
            self.assets.append(a["href"])


_PARSED: dict[Path, _Parsed] = {}


def parsed(path: Path) -> _Parsed:
    if path not in _PARSED:
        p = _Parsed()
        p.feed(path.read_text(encoding="utf-8"))
        _PARSED[path] = p
    return _PARSED[path]


def _is_external(url: str) -> bool:
    return bool(urlsplit(url).scheme) or url.startswith("//")


def crawl(html: Path) -> list[Path]:
    """Every HTML page reachable from index.html through the site's own links."""
    seen: list[Path] = []
    todo = [html / "index.html"]
    while todo:
        page = todo.pop()
        if page in seen:
            continue
        seen.append(page)
        for href in parsed(page).links:
            if _is_external(href):
                continue
            target = unquote(urlsplit(href).path)
            if not target:
                continue
            path = (page.parent / target).resolve()
            if path.suffix == ".html" and path.is_file() and html in path.parents:
                todo.append(path)
    return sorted(seen)


EXTRA_PAGES = ("search.html", "genindex.html", "py-modindex.html")


@pytest.fixture(scope="session")
def pages(site: Path) -> list[Path]:
    """The pages reachable from index.html, plus Sphinx's search page and indices."""
    extra = [site / name for name in EXTRA_PAGES if (site / name).is_file()]
    return sorted(set(crawl(site)) | set(extra))


def _name(page: Path) -> str:
    return page.relative_to(HTML).with_suffix("").as_posix()


# ------------------------------------------------------------------------------------------
# the HTML itself (no browser needed)
# ------------------------------------------------------------------------------------------


def test_site_lists_every_page(pages: list[Path]) -> None:
    names = {_name(p) for p in pages}
    expected = {
        "index",
        "claims",
        "gallery",
        "errata",
        "environment",
        "readme",
        "references",
        "api/index",
    }
    expected |= {page_of(key) for key in notebook_keys(ROOT)}
    assert "beyond/arena" in expected, "the arena has no page"
    assert expected <= names, f"pages not reachable from index.html: {sorted(expected - names)}"
    built = {_name(p) for p in HTML.rglob("*.html") if "_static" not in p.parts}
    assert built <= names, f"pages built but not reachable: {sorted(built - names)}"


def test_no_internal_link_is_broken(pages: list[Path]) -> None:
    """Every link and asset of every page exists; every #fragment names an element of its page."""
    broken: list[str] = []
    for page in pages:
        p = parsed(page)
        for href in p.links + p.assets:
            if _is_external(href) or href.startswith(("mailto:", "javascript:")):
                continue
            parts = urlsplit(href)
            target, frag = parts.path, parts.fragment
            path = (page.parent / unquote(target)).resolve() if target else page
            if not path.exists():
                broken.append(f"{_name(page)}: {href} (no such file)")
            elif frag and path.suffix == ".html" and unquote(frag) not in parsed(path).ids:
                broken.append(f"{_name(page)}: {href} (no element #{frag})")
    assert not broken, "\n".join(broken)


def test_no_remote_script_style_or_font(pages: list[Path]) -> None:
    """Nothing is fetched from the network at view time (MathJax is served by the site)."""
    remote = [f"{_name(p)}: {a}" for p in pages for a in parsed(p).assets if _is_external(a)]
    assert not remote, "\n".join(remote)
    lee = (HTML / "papers" / "lee2020.html").read_text()
    assert "_static/mathjax/tex-svg.js" in lee
    assert (HTML / "_static" / "mathjax" / "tex-svg.js").is_file()


def test_landing_verdict_table_matches_readme(site: Path) -> None:
    text = (site / "index.html").read_text()
    table = re.search(r'<table class="[^"]*secest-verdicts.*?</table>', text, flags=re.S)
    assert table, "the landing page has no verdict table"
    rows = re.findall(r"<tr.*?</tr>", table.group(0), flags=re.S)[1:]
    verdicts = readme_papers(ROOT)
    assert len(rows) == len(paper_keys(ROOT))
    for key, row in zip(paper_keys(ROOT), rows, strict=True):
        assert f"papers/{key}.html" in row
        tag = verdicts[key]["verdict"]
        assert f">{tag}</span>" in row.replace("&#172;", "¬"), (key, tag)


def test_claims_matrix_lists_every_claim(site: Path) -> None:
    text = (site / "claims.html").read_text()
    for key in paper_keys(ROOT):
        claims = json.loads((ROOT / "figures" / key / "claims.json").read_text())
        for cid, entry in claims.items():
            anchor = f'id="{claim_label(key, cid)}"'
            assert anchor in text, (key, cid)
            row = text[text.index(anchor) : text.index("</tr>", text.index(anchor))]
            assert f"secest-badge-{entry['verdict']}" in row, (key, cid, entry["verdict"])


def test_gallery_and_paper_pages_carry_every_manifest_figure(site: Path) -> None:
    gallery = (site / "gallery.html").read_text()
    for key, entry in load_manifest(ROOT).items():
        page = (site / f"{page_of(key)}.html").read_text()
        for fig in entry["figures"]:
            for f in fig["files"]:
                assert Path(f).name in gallery, (key, f)
                if f.endswith(".png"):
                    fid = "fig-" + re.sub(r"[^a-z0-9]+", "-", f"{key}-{Path(f).stem}".lower())
                    assert f'id="{fid}"' in page, (key, fid)


def test_the_arena_is_on_the_site_but_not_a_paper(site: Path) -> None:
    """The arena has its own page under "Beyond the papers", its findings in the claims matrix,
    its figures numbered, and no row in the papers' verdict table."""
    assert beyond_keys(ROOT) == ["arena"] and "arena" not in paper_keys(ROOT)
    index = (site / "index.html").read_text()
    assert "beyond/arena.html" in index and "Beyond the papers" in index
    table = re.search(r'<table class="[^"]*secest-verdicts.*?</table>', index, flags=re.S).group(0)
    assert "arena" not in table
    claims = (site / "claims.html").read_text()
    for cid in json.loads((ROOT / "figures" / "arena" / "claims.json").read_text()):
        assert f'id="{claim_label("arena", cid)}"' in claims, cid
    page = (site / "beyond" / "arena.html").read_text()
    assert "Beyond the papers" in page and 'id="fig-arena-extra-heatmap-tuned"' in page


def test_errata_links_land_on_the_deviations_heading(site: Path) -> None:
    errata = site / "errata.html"
    links = [h for h in parsed(errata).links if h.startswith("papers/") and "#" in h]
    assert {h.split("/")[1].split(".")[0] for h in links} == set(paper_keys(ROOT))
    for href in links:
        target, frag = urldefrag(href)
        html = (site / target).read_text()
        m = re.search(rf'<section id="{re.escape(frag)}">\s*<h2>([^<]*)', html)
        assert m and m.group(1).startswith("Deviations from the paper"), href


def test_downloads_are_the_committed_files(site: Path) -> None:
    for key in notebook_keys(ROOT):
        page = site / f"{page_of(key)}.html"
        downloads = [h for h in parsed(page).links if h.startswith("../_downloads/")]
        for name in (f"{key}.ipynb", f"{key}.py", "claims.json"):
            hits = [h for h in downloads if h.endswith("/" + name)]
            assert hits, (key, name)
            repo_file = ROOT / ("figures/" + key if name == "claims.json" else "notebooks") / name
            assert (page.parent / hits[0]).read_bytes() == repo_file.read_bytes()
        source = site / "_sources" / f"{page_of(key)}.ipynb"
        assert source.read_bytes() == (ROOT / "notebooks" / f"{key}.ipynb").read_bytes()


# ------------------------------------------------------------------------------------------
# the browser
# ------------------------------------------------------------------------------------------


@pytest.fixture(scope="session")
def browser_context(site: Path) -> Iterator[Any]:
    if not CHROMIUM.exists():
        message = (
            "NO BROWSER: /usr/bin/chromium is missing, so the site was NOT checked in a browser "
            "(pages, figures, maths, screenshots). Install Debian's chromium "
            "(`apt-get install chromium`; .ci/run does) and run `make test` again."
        )
        if os.environ.get("SECEST_REQUIRE_BROWSER") == "1":
            pytest.fail(message + " SECEST_REQUIRE_BROWSER=1 makes this a failure.")
        print("\n" + "!" * 100 + "\n" + message + "\n" + "!" * 100, file=sys.stderr)
        pytest.skip(message)
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory(prefix="secest-chromium-") as profile, sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile,
            executable_path=str(CHROMIUM),
            headless=True,
            args=CHROMIUM_FLAGS,
            viewport={"width": 1280, "height": 900},
        )
        try:
            yield context
        finally:
            context.close()


@pytest.fixture(scope="session")
def server(site: Path) -> Iterator[str]:
    class Quiet(SimpleHTTPRequestHandler):
        def log_message(self, *args: Any) -> None:
            pass

    httpd = ThreadingHTTPServer(("127.0.0.1", 0), partial(Quiet, directory=str(site)))
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()


_TYPESET = """async () => {
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
  }
  const root = document.querySelector('main') || document.body;
  const copy = root.cloneNode(true);
  copy.querySelectorAll('pre, code, script, style, mjx-container, .MathJax, textarea').forEach(e => e.remove());
  return {
    text: copy.innerText,
    math: document.querySelectorAll('.math').length,
    typeset: document.querySelectorAll('mjx-container').length,
    mathjax: typeof window.MathJax === 'object' && !!window.MathJax.version,
  };
}"""


class _Tab:
    """One browser tab that opens page after page (a new tab per page takes twice as long).

    The errors and outside requests of each navigation are collected afresh by :meth:`open`.
    """

    def __init__(self, context: Any) -> None:
        self.page = context.new_page()
        self.errors: list[str] = []
        self.outside: list[str] = []
        self.page.on("console", self._console)
        self.page.on("pageerror", lambda e: self.errors.append(f"page error: {e}"))
        self.page.on("request", self._request)
        self.page.on("response", self._response)

    def _console(self, msg: Any) -> None:
        where = (msg.location or {}).get("url", "")
        if msg.type == "error" and not where.endswith("/favicon.ico"):
            self.errors.append(f"console error: {msg.text} ({where})")

    def _request(self, req: Any) -> None:
        parts = urlsplit(req.url)
        if parts.scheme not in ("file", "data", "blob") and parts.hostname not in (
            "127.0.0.1",
            "localhost",
        ):
            self.outside.append(req.url)

    def _response(self, resp: Any) -> None:
        if resp.status >= 400 and not resp.url.endswith("/favicon.ico"):
            self.errors.append(f"HTTP {resp.status}: {resp.url}")

    def open(self, url: str) -> tuple[Any, list[str], list[str]]:
        """Open ``url``; return the page, its console/page errors and any request that left
        the machine."""
        self.errors, self.outside = [], []
        self.page.goto(url, wait_until="load")
        return self.page, self.errors, self.outside


def _open(context: Any, url: str) -> tuple[Any, list[str], list[str]]:
    """Open ``url`` in a new tab (see :class:`_Tab`)."""
    return _Tab(context).open(url)


def _check_maths(page: Any, name: str) -> list[str]:
    info = page.evaluate(_TYPESET)
    problems = []
    for raw in list(RAW_MATH.finditer(info["text"]))[:10]:
        start = max(raw.start() - 60, 0)
        problems.append(f"{name}: raw maths left: …{info['text'][start : raw.end() + 40]!r}")
    if info["math"] and not (info["mathjax"] and info["typeset"]):
        problems.append(f"{name}: {info['math']} maths elements but MathJax typeset {info['typeset']}")
    return problems


def _check_figures(page: Any, key: str) -> list[str]:
    """Every PNG the manifest lists for ``key`` is a loaded image in its numbered figure."""
    ids = [
        "fig-" + re.sub(r"[^a-z0-9]+", "-", f"{key}-{Path(f).stem}".lower())
        for fig in load_manifest(ROOT).get(key, {}).get("figures", [])
        for f in fig["files"]
        if f.endswith(".png")
    ]
    found = page.evaluate(
        """ids => ids.map(id => {
             const imgs = document.querySelectorAll(`figure[id="${id}"] img`);
             return [id, imgs.length, imgs.length ? (imgs[0].complete ? imgs[0].naturalWidth : 0) : 0];
           })""",
        ids,
    )
    problems = []
    for fid, count, width in found:
        if count != 1:
            problems.append(f"{key}: figure#{fid} holds {count} images")
        elif not width:  # a lazy image (loading="lazy") loads when it comes into view
            img = page.locator(f"figure[id='{fid}'] img")
            img.scroll_into_view_if_needed()
            from playwright.sync_api import TimeoutError as PlaywrightTimeout

            try:
                page.wait_for_function("i => i.complete && i.naturalWidth > 0", arg=img.element_handle(),
                                       timeout=10_000)
            except PlaywrightTimeout:
                problems.append(f"{key}: figure#{fid}: image not loaded (naturalWidth 0)")
    return problems


def _errata_targets(html: Path) -> dict[str, list[str]]:
    """Paper page -> the #fragments the errata page links to on it."""
    targets: dict[str, list[str]] = {}
    for href in parsed(html / "errata.html").links:
        parts = urlsplit(href)
        if parts.path.startswith("papers/") and parts.fragment:
            targets.setdefault(parts.path.removesuffix(".html"), []).append(parts.fragment)
    return targets


def _land(page: Any, url: str, frag: str) -> dict[str, Any]:
    """Follow ``url#frag`` (same document): the heading there and where it lands in the view."""
    page.goto(f"{url}#{frag}")
    page.wait_for_timeout(100)
    return page.evaluate(
        """frag => {
             const e = document.getElementById(frag);
             if (!e) return {heading: null, top: null};
             const h = e.matches('h1,h2,h3,h4') ? e : e.querySelector('h1,h2,h3,h4');
             return {heading: h ? h.innerText : null, top: (h || e).getBoundingClientRect().top};
           }""",
        frag,
    )


@pytest.fixture(scope="session")
def browsed(browser_context: Any, server: str, pages: list[Path]) -> dict[str, dict[str, Any]]:
    """Open every page once (served on 127.0.0.1): findings per page; a screenshot of each."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    for old in [*SHOTS.glob("*.png"), *SHOTS.glob("*.jpg")]:
        old.unlink()
    found: dict[str, dict[str, Any]] = {}
    errata = _errata_targets(HTML)
    tab = _Tab(browser_context)
    for path in pages:
        name = _name(path)
        t0 = time.perf_counter()
        url = f"{server}/{path.relative_to(HTML).as_posix()}"
        page, errors, outside = tab.open(url)
        maths = _check_maths(page, name)
        figures = (_check_figures(page, name.split("/")[1])
                   if name.startswith(("papers/", "beyond/")) else [])
        # JPEG: a full page of 20 000 px encodes several times faster than PNG, legible for
        # people; JPEG cannot exceed 65 535 px, so a taller page is saved as PNG
        tall = FULL_PAGE and page.evaluate("document.documentElement.scrollHeight") > JPEG_MAX_PX
        shot = SHOTS / (name.replace("/", "__") + (".png" if tall else ".jpg"))
        page.screenshot(path=str(shot), full_page=FULL_PAGE,
                        **({} if tall else {"type": "jpeg", "quality": 80}))
        landings = {frag: _land(page, url, frag) for frag in errata.get(name, [])}
        found[name] = {
            "errors": errors,
            "outside": outside,
            "maths": maths,
            "figures": figures,
            "errata": landings,
        }
        if os.environ.get("SECEST_SITE_TIMING"):
            print(f"{name}: {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    tab.page.close()
    return found


def test_every_page_opens_without_error_or_outside_request(browsed: dict[str, Any]) -> None:
    problems = [f"{n}: {e}" for n, f in browsed.items() for e in f["errors"]]
    problems += [
        f"{n}: request leaves the machine: {u}" for n, f in browsed.items() for u in f["outside"]
    ]
    assert not problems, "\n".join(problems)


def test_maths_is_typeset_on_every_page(browsed: dict[str, Any]) -> None:
    problems = [p for f in browsed.values() for p in f["maths"]]
    assert not problems, "\n".join(problems)


def test_paper_pages_show_every_manifest_figure(browsed: dict[str, Any]) -> None:
    assert {page_of(key) for key in notebook_keys(ROOT)} <= set(browsed)
    problems = [p for f in browsed.values() for p in f["figures"]]
    assert not problems, "\n".join(problems)


def test_a_screenshot_of_every_page(browsed: dict[str, Any]) -> None:
    shots = [*SHOTS.glob("*.jpg"), *SHOTS.glob("*.png")]
    assert sorted(p.stem for p in shots) == sorted(name.replace("/", "__") for name in browsed)
    assert all(p.stat().st_size > 10_000 for p in shots)


def test_errata_links_land_on_deviations_in_browser(browsed: dict[str, Any]) -> None:
    """Following each ERRATA link puts its paper's "Deviations from the paper" heading in view."""
    landings = {(n, frag): hit for n, f in browsed.items() for frag, hit in f["errata"].items()}
    assert {n for n, _ in landings} == {f"papers/{key}" for key in paper_keys(ROOT)}
    for (name, frag), hit in landings.items():
        assert hit["heading"] and hit["heading"].startswith("Deviations from the paper"), (
            name,
            frag,
            hit,
        )
        assert -5 <= hit["top"] < 300, f"{name}#{frag}: the heading lands {hit['top']} px from the top"


@pytest.mark.parametrize("name", ["index", "papers/lee2020"])
def test_opens_from_disk_without_network(browser_context: Any, site: Path, name: str) -> None:
    """``file://`` with every network request refused: the landing page and maths still render."""
    blocked: list[str] = []

    def refuse(route: Any) -> None:
        blocked.append(route.request.url)
        route.abort()

    remote = re.compile(r"^https?://")
    browser_context.route(remote, refuse)
    try:
        page, errors, outside = _open(browser_context, (site / f"{name}.html").as_uri())
        problems = _check_maths(page, name) + errors + [f"request: {u}" for u in outside + blocked]
        if name == "index":
            table = page.locator("table.secest-verdicts")
            assert table.is_visible()
            for key in paper_keys(ROOT):
                assert key in table.inner_text()
        assert page.locator("mjx-container").count() > 0, f"{name}: no typeset maths"
        page.close()
    finally:
        browser_context.unroute(remote)
    assert not problems, "\n".join(problems)


# ------------------------------------------------------------------------------------------
# the generators, on inputs the committed files do not (yet) exercise
# ------------------------------------------------------------------------------------------


def test_claim_row_shows_interval_premise_robustness_and_section() -> None:
    from secest.repro.site import CLAIM_COLUMNS, _claim_row

    heads = [
        (2, "Fig. 4 — position $x_{1,k}$ and its estimates", "fig-4--position--and-its-estimates"),
        (2, "Claims", "claims"),
    ]
    entry = {
        "paper": "the filter is *stable*",
        "source": "Theorem 2, (34)",
        "check": "max |e| <= 1",
        "measured": {"rate": 0.97, "runs": 300},
        "key": "rate",
        "interval": {"low": 0.95, "high": 0.985, "level": 0.95, "method": "Wilson"},
        "threshold": 0.9,
        "holds": True,
        "premise": {"statement": "(42)-(43) hold", "holds": False},
        "verdict": "undetermined",
        "robustness": {
            "fraction_holds": 0.4,
            "interval": {"low": 0.3, "high": 0.5, "level": 0.95, "method": "Wilson"},
            "region": {"p": "< 0.2"},
            "points": 64,
        },
        "section": "Fig. 4 — position $x_{1,k}$ and its estimates",
    }
    rows = _claim_row("ding2020", "C3", entry, heads, "claims")
    text = "\n".join(rows)
    assert rows[0] == "* - (claim-ding2020-c3)=" and len(CLAIM_COLUMNS) == 5
    assert sum(r.startswith("  - ") for r in rows) == len(CLAIM_COLUMNS) - 1  # five cells
    assert "{badge}`undetermined`" in text
    assert "holds in 40 % of the declared space" in text and "holds at this run" in text
    assert "95 % interval \\[0.95, 0.985\\] (Wilson)" in text
    assert "**premise** (does not hold)" in text
    assert "source: Theorem 2, (34)" in text
    assert "the filter is \\*stable\\*" in text  # the paper's words are text, not markup
    assert "rate: 0.97" in text
    assert "[**C3**](papers/ding2020.ipynb#fig-4--position--and-its-estimates)" in text
    on_page = "\n".join(_claim_row("ding2020", "C3", entry, heads, "claims", on_page=True))
    assert "(ding2020-claim-c3)=" in on_page
    assert "[**C3**](ding2020.ipynb#fig-4--position--and-its-estimates)" in on_page
    no_section = {k: v for k, v in entry.items() if k not in ("section", "source")}
    text = "\n".join(_claim_row("ding2020", "C3", no_section, heads, "claims"))
    assert "[**C3**](papers/ding2020.ipynb#claims)" in text
    assert "source: —" in text
    optional = {**entry, "basis": "by-construction", "runs": 300, "decides": False,
                "verdict": "not-checked"}
    text = "\n".join(_claim_row("ding2020", "C3", optional, heads, "claims"))
    assert "true by construction: not evidence" in text and "runs: 300" in text
    assert "does not decide the verdict" in text and "{badge}`not-checked`" in text


def test_claim_row_rejects_a_section_that_names_no_heading() -> None:
    from secest.repro.site import SiteError, _claim_row

    entry = {
        "paper": "p",
        "check": "c",
        "measured": 1,
        "threshold": 1,
        "holds": True,
        "verdict": "holds",
    }
    with pytest.raises(SiteError, match="names no heading"):
        _claim_row(
            "lee2020", "C1", {**entry, "section": "No such section"}, [(2, "Claims", "claims")], "claims"
        )


def test_format_value_is_short() -> None:
    from secest.repro.site import format_value

    assert format_value(0.123456789) == "0.1235"
    assert format_value(True) == "true"
    assert format_value(list(range(10))) == "[0, 1, 2, 3, 4, 5, … (4 more)]"
    assert format_value({"a": {"b": 1e-9}, "c": [1, 2]}) == "a.b: 1e-09; c: [1, 2]"
    assert format_value(None) == "—"


def test_protect_table_maths_only_mends_rows_split_inside_maths() -> None:
    from secest.repro.site import protect_table_maths

    table = "| a | b |\n|---|---|\n| $|z|>3$ | ok |\n| $x$ | `$|` |"
    fixed = protect_table_maths(table).split("\n")
    assert fixed[2] == "| $\\vert z\\vert >3$ | ok |"
    assert fixed[3] == "| $x$ | `$|` |"  # same cell count as the header: left alone
    assert protect_table_maths("not a table $|x|$") == "not a table $|x|$"


def test_heading_anchors_match_the_built_pages(site: Path) -> None:
    """The anchors secest.repro.site computes for notebook headings (claim links) exist on the pages."""
    from secest.repro.site import notebook_headings, read_notebook

    for key in notebook_keys(ROOT):
        ids = parsed(site / f"{page_of(key)}.html").ids
        heads = notebook_headings(read_notebook(ROOT / "notebooks" / f"{key}.ipynb"))
        missing = [(title, slug) for level, title, slug in heads if level > 1 and slug not in ids]
        assert not missing, (key, missing)


# ------------------------------------------------------------------------------------------
# issue #31: folding, claim links, one claims table per page
# ------------------------------------------------------------------------------------------


def test_fold_tags_keep_the_algorithm_visible() -> None:
    from secest.repro.site import fold_tags

    def code(src: str, outputs: int = 1) -> dict:
        return {"cell_type": "code", "source": src, "outputs": [{}] * outputs, "metadata": {}}

    assert fold_tags(code("show_source(M.fuse)\nshow_source(M.gain, after='  x')")) == []
    assert fold_tags(code("show_source(\n    M.fuse,\n    after='    N, n',\n)")) == []
    assert fold_tags(code("x = 1\nshow_source(M.fuse)")) == ["hide-input"]  # mixed: folded
    assert fold_tags(code("import numpy as np")) == ["hide-input"]
    assert fold_tags(code("display(Markdown(spaces.provenance_markdown('lee2020')))")) == [
        "hide-input",
        "hide-output",
    ]
    assert fold_tags(code("results.write_claims(claims, results_path)")) == ["hide-input", "hide-output"]
    assert fold_tags(code("results.write_claims(claims, results_path)", outputs=0)) == ["hide-input"]
    assert fold_tags(code("%matplotlib inline")) == ["hide-input"]
    assert fold_tags({"cell_type": "markdown", "source": "show_source(x)"}) == []


def test_link_claim_ids_touches_prose_only() -> None:
    from secest.repro.site import link_claim_ids

    ids = ["C1", "C1_nd", "C2a", "X3"]
    text = "\n".join(
        [
            "## C1 in a heading stays",
            "C1 holds, C1_nd too, **C2a** fails; X3 (ours). C10 is not a claim, nor xC1.",
            "Maths $C1 + C_1$, code `C1`, a [link C1](#x) and {ref}`C2a <y>` stay.",
            "```",
            "C1 in a fence",
            "```",
        ]
    )
    out = link_claim_ids(text, "guo2023", ids).split("\n")
    assert out[0] == "## C1 in a heading stays"
    assert out[1] == (
        "{ref}`C1 <guo2023-claim-c1>` holds, {ref}`C1_nd <guo2023-claim-c1-nd>` too, "
        "**{ref}`C2a <guo2023-claim-c2a>`** fails; {ref}`X3 <guo2023-claim-x3>` (ours). "
        "C10 is not a claim, nor xC1."
    )
    assert out[2:] == text.split("\n")[2:]


def test_every_notebook_page_has_one_claims_table_with_the_same_columns(site: Path) -> None:
    from secest.repro.site import CLAIM_COLUMNS, page_claim_label

    for key in notebook_keys(ROOT):
        html = (site / f"{page_of(key)}.html").read_text()
        tables = re.findall(r'<table class="[^"]*secest-claims[" ].*?</table>', html, flags=re.S)
        assert len(tables) == 1, (key, len(tables))
        heads = [re.sub(r"<[^>]+>", "", h).strip()
                 for h in re.findall(r"<th[^>]*>(.*?)</th>", tables[0], flags=re.S)]
        expected = list(CLAIM_COLUMNS)
        if key == "arena":
            expected[1] = "The finding (ours)"
        assert heads == expected, (key, heads)
        claims = json.loads((ROOT / "figures" / key / "claims.json").read_text())
        ids = parsed(site / f"{page_of(key)}.html").ids
        for cid, entry in claims.items():
            assert page_claim_label(key, cid) in ids, (key, cid)
            row = tables[0][tables[0].index(f'id="{page_claim_label(key, cid)}"'):]
            row = row[: row.index("</tr>")]
            assert f"secest-badge-{entry['verdict']}" in row, (key, cid)
        # the claim ids of the prose link to the rows of this table
        links = [h for h in parsed(site / f"{page_of(key)}.html").links if "-claim-" in h]
        assert links and all(h.split("#")[-1] in ids for h in links), key


def test_code_is_folded_by_the_stated_rule(site: Path) -> None:
    """Every code cell's input is folded except the show_source-only cells; the listings that
    show_source prints (the algorithm) are never folded; only the two outputs the rule names are."""
    from secest.repro.site import fold_tags, read_notebook

    for key in notebook_keys(ROOT):
        nb = read_notebook(ROOT / "notebooks" / f"{key}.ipynb")
        code = [c for c in nb["cells"] if c["cell_type"] == "code"]
        tags = [fold_tags(c) for c in code]
        html = (site / f"{page_of(key)}.html").read_text()
        cells = re.findall(r'<div class="cell(?: [^"]*)? docutils container">', html)
        assert len(cells) == len(code), (key, len(cells), len(code))
        assert sum("tag_hide-input" in c for c in cells) == sum("hide-input" in t for t in tags)
        assert sum("tag_hide-output" in c for c in cells) == sum("hide-output" in t for t in tags)
        listings = [c for c, t in zip(code, tags, strict=True) if "show_source(" in "".join(c["source"])]
        assert all(c.get("outputs") for c in listings), key
        if key != "arena":
            assert listings, f"{key}: no algorithm shown"
            assert not any("hide-output" in fold_tags(c) for c in listings), key


def test_sentence_cut_skips_abbreviations_and_initials() -> None:
    from secest.repro.site import sentence_cut

    text = "See Fig. 2 and Sec. V. of the paper, e.g. Here. It ends here. Then more (Lemma 1.) Next."
    cut = sentence_cut(text, 5)
    assert text[:cut] == "See Fig. 2 and Sec. V. of the paper, e.g. Here."
    assert text[: sentence_cut(text, cut + 1)] == text[: text.index(" Then")]
    assert text[: sentence_cut(text, text.index("Then"))].endswith("(Lemma 1.)")
    assert sentence_cut("no full stop at all", 0) is None
    assert sentence_cut("One. Two.", 3) == 4  # the end at or past the lead


def test_the_listing_box_in_the_css_is_the_stated_one() -> None:
    from secest.repro.site import LISTING_LINES

    css = (ROOT / "docs" / "_static" / "secest.css").read_text()
    assert f"div.highlight pre {{ max-height: {1.5 * LISTING_LINES:g}em; max-height: {LISTING_LINES}lh;" in css


_FOLDED = re.compile(
    r'<p>((?:(?!</p>).)*?)<input type="checkbox" class="secest-more-toggle" id="([\w-]+)">'
    r'<label class="secest-more-open" for="\2">… more \((\d+) words\)</label>'
    r'<span class="secest-more-rest">((?:(?!</p>).)*?) <label class="secest-more-close" for="\2">less'
    r"</label></span></p>",
    flags=re.S,
)


def _text(fragment: str) -> str:
    return html_lib.unescape(re.sub(r"<[^>]+>", "", fragment))


def test_prose_is_folded_by_the_stated_rule(site: Path) -> None:
    """Every folded paragraph keeps a lead of at least PROSE_LEAD_CHARS characters ending a
    sentence and was longer than FOLD_PROSE_CHARS; its toggle counts the folded words; every end
    matter section of a notebook page is folded after its first paragraph, and none else."""
    from secest.repro.site import END_MATTER, FOLD_PROSE_CHARS, PROSE_LEAD_CHARS

    for key in notebook_keys(ROOT):
        html = (site / f"{page_of(key)}.html").read_text()
        folds = _FOLDED.findall(html)
        assert len(folds) == html.count('class="secest-more-toggle"') > 5, key  # each one well formed
        for lead, ident, words, rest in folds:
            lead_text, rest_text = _text(lead), _text(rest)
            assert len(lead_text) >= PROSE_LEAD_CHARS * 0.9, (key, ident, lead_text)  # maths as TeX, x_{k} as HTML
            assert re.search(r"[.!?][)\]’”\"']?$", lead_text.rstrip()), (key, ident, lead_text[-40:])
            assert len(lead_text) + len(rest_text) > 0.9 * FOLD_PROSE_CHARS, (key, ident)  # idem
            n = len(rest_text.split())  # the HTML's maths keeps its \( \) delimiters: near, not equal
            assert abs(int(words) - n) <= max(2, n // 20), (key, ident, words, n)
        sections = re.findall(r'<section id="[^"]+">\s*<h2>(.*?)<a class="headerlink"(.*?)(?=<section id=|\Z)',
                              html, flags=re.S)
        end = [_text(t).strip() for t, body in sections if "secest-section-more" in body]
        titles = [_text(t).strip() for t, _ in sections]
        assert end == [t for t in titles if t in END_MATTER], (key, end)
        assert len(end) >= 2, (key, titles)  # the claims and the deviations at least


def test_a_folded_paragraph_opens_and_closes(browser_context: Any, server: str) -> None:
    page = browser_context.new_page()
    page.goto(f"{server}/papers/lee2020.html", wait_until="load")
    para = page.locator("p:has(> input.secest-more-toggle)").nth(3)
    rest = para.locator("span.secest-more-rest")
    para.scroll_into_view_if_needed()
    assert not rest.is_visible()
    para.locator("label.secest-more-open").click()
    assert rest.is_visible() and not para.locator("label.secest-more-open").is_visible()
    rest.locator("label.secest-more-close").click()
    assert not rest.is_visible()
    box = page.locator("details.secest-section-more").first
    assert not box.evaluate("d => d.open")
    box.locator("summary").click()
    assert box.evaluate("d => d.open")
    page.close()


def test_every_page_names_its_build_commit_and_the_citation(site: Path) -> None:
    from secest.repro.site import build_commit, citation

    commit = build_commit(ROOT).split()[0]
    for name in ("index", "papers/lee2020", "api/index"):
        assert f"Built from commit <code>{commit}" in (site / f"{name}.html").read_text(), name
    install = (site / "install.html").read_text()
    assert citation(ROOT)["authors"] in install and "CITATION.cff" in install
    archives = re.findall(r'href="(_downloads/[0-9a-f]+/secest-[0-9a-f]+\.tar\.gz)"', install)
    if commit == "unknown":  # built from an archive, not a git work tree: nothing to archive
        assert not archives
        return
    assert len(set(archives)) == 1, "install page: no single link to the repository's source archive"
    with tarfile.open(site / archives[0]) as tar:
        names = tar.getnames()
    stem = Path(archives[0]).name.removesuffix(".tar.gz")
    assert {f"{stem}/Makefile", f"{stem}/environment.lock", f"{stem}/notebooks/lee2020.py"} <= set(names)
    assert "the secest authors" not in (site / "index.html").read_text()
    assert (site / "_static" / "favicon.svg").is_file()
    assert 'rel="icon"' in (site / "index.html").read_text()
    assert "_modules/secest/methods/lee2020.html" in (site / "api" / "methods.lee2020.html").read_text()


# ------------------------------------------------------------------------------------------
# issue #31 in the browser: two widths, every equation, menus, page heights, load time
# ------------------------------------------------------------------------------------------

WIDTHS = {"desktop": (1280, 900), "phone": (390, 844)}
REPORT = ROOT / "build" / "site-report.txt"
# the paper pages' heights at 1280 px before issue #31 (commit 8dce945, measured by this test's
# predecessor probe); the target is at most 40 % of each
HEIGHT_BEFORE = {"ding2020": 58883, "guo2023": 54624, "lee2020": 63205, "li2025": 62568,
                 "ma2021": 66693}

_LAYOUT = """async () => {
  if (window.MathJax && MathJax.startup && MathJax.startup.promise) {
    await MathJax.startup.promise;
    const doc = MathJax.startup.document;
    if (doc && doc.lazyTypesetAll) await doc.lazyTypesetAll();  // ui/lazy: typeset every equation
  }
  const root = document.documentElement;
  const article = document.querySelector('.bd-article') || document.body;
  const col = article.getBoundingClientRect();
  const boxOf = el => {
    for (let a = el.parentElement; a && a !== document.body; a = a.parentElement) {
      if (getComputedStyle(a).overflowX !== 'visible') return a;
    }
    return null;
  };
  const eqs = [...document.querySelectorAll('mjx-container[display="true"]')];
  const clipped = [];
  for (const c of eqs) {
    const svg = c.querySelector('svg');
    if (!svg) { clipped.push(['not typeset', (c.parentElement.id || '')]); continue; }
    const s = svg.getBoundingClientRect();
    const box = boxOf(svg);
    const b = box ? box.getBoundingClientRect() : col;
    const ox = box ? getComputedStyle(box).overflowX : 'visible';
    const scrolls = box && (ox === 'auto' || ox === 'scroll') && box.scrollWidth > box.clientWidth;
    const name = (c.closest('div.math') || c).id || (c.getAttribute('aria-label') || '').slice(0, 40);
    if (s.left < b.left - 1) clipped.push(['left', name, Math.round(b.left - s.left)]);
    else if (s.right > b.right + 1 && !scrolls) clipped.push(['right', name, Math.round(s.right - b.right)]);
    if (!box && (s.left < col.left - 1 || s.right > col.right + 1)) clipped.push(['column', name]);
  }
  const nav = performance.getEntriesByType('navigation')[0];
  const bytes = performance.getEntriesByType('resource').reduce((a, e) => a + (e.encodedBodySize || 0), 0)
    + (nav ? nav.encodedBodySize : 0);
  return {
    sideways: root.scrollWidth - root.clientWidth,
    height: root.scrollHeight,
    equations: eqs.length,
    displayed: document.querySelectorAll('div.math').length,
    clipped,
    load: nav ? nav.loadEventStart / 1000 : null,
    bytes,
  };
}"""


@pytest.fixture(scope="session")
def layout(browser_context: Any, server: str, pages: list[Path]) -> dict[str, dict[str, Any]]:
    """Every page at 1280 x 900 and at 390 x 844: sideways scroll, every display equation's box,
    height, load event and bytes. A report of the paper pages goes to build/site-report.txt."""
    found: dict[str, dict[str, Any]] = {}
    for width, (w, h) in WIDTHS.items():
        tab = browser_context.new_page()
        tab.set_viewport_size({"width": w, "height": h})
        for path in pages:
            tab.goto(f"{server}/{path.relative_to(HTML).as_posix()}", wait_until="load")
            found.setdefault(_name(path), {})[width] = tab.evaluate(_LAYOUT)
        tab.close()
    largest = max(found, key=lambda n: (HTML / f"{n}.html").stat().st_size)  # the largest document
    tab = browser_context.new_page()
    loads = []
    for _ in range(3):  # the best of three: other processes on the machine add noise, not weight
        tab.goto(f"{server}/{largest}.html", wait_until="load")
        loads.append(tab.evaluate("performance.getEntriesByType('navigation')[0].loadEventStart / 1000"))
    tab.close()
    found["_largest"] = {"name": largest, "load": min(loads), "loads": loads,
                         "bytes": found[largest]["desktop"]["bytes"]}
    lines = ["paper page heights at 1280 px (before issue #31 -> now, share):"]
    for key, before in HEIGHT_BEFORE.items():
        now = found[f"papers/{key}"]["desktop"]["height"]
        lines.append(f"  {key}: {before} -> {now} px ({100 * now / before:.1f} %)")
    lines.append(f"largest page: {largest} ({(HTML / f'{largest}.html').stat().st_size / 1e3:.0f} kB "
                 f"of HTML, {found['_largest']['bytes'] / 1e6:.2f} MB loaded by its load event), "
                 f"load event {min(loads):.2f} s (best of {', '.join(f'{t:.2f}' for t in loads)})")
    lines.append("paper pages' load events (one load each): " + ", ".join(
        f"{key} {found[f'papers/{key}']['desktop']['load']:.2f} s" for key in HEIGHT_BEFORE))
    eqs = {wd: sum(f[wd]["equations"] for n, f in found.items() if n != "_largest") for wd in WIDTHS}
    lines.append(f"display equations measured: {eqs['desktop']} at 1280 px, {eqs['phone']} at 390 px")
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text("\n".join(lines) + "\n")
    print("\n" + "\n".join(lines))
    return found


def test_no_display_equation_is_clipped(layout: dict[str, Any]) -> None:
    """Every display equation lies inside its column or scrolls in a box of its own, at both widths;
    none overflows to the left, where it could not be scrolled to."""
    problems = [f"{n} ({wd}): {c}" for n, f in layout.items() if n != "_largest"
                for wd in WIDTHS for c in f[wd]["clipped"]]
    for name, found in layout.items():  # every display equation of every page was measured
        for wd in WIDTHS if name != "_largest" else ():
            assert found[wd]["equations"] >= found[wd]["displayed"], (name, wd, found[wd])
    assert sum(f["phone"]["equations"] for n, f in layout.items() if n != "_largest") > 30
    assert not problems, "\n".join(problems[:40])


def test_no_page_scrolls_sideways_on_a_phone(layout: dict[str, Any]) -> None:
    wide = {n: f["phone"]["sideways"] for n, f in layout.items() if n != "_largest"}
    assert not {n: px for n, px in wide.items() if px > 0}, wide


def test_paper_pages_are_at_most_40_percent_of_their_former_height(layout: dict[str, Any]) -> None:
    heights = {key: layout[f"papers/{key}"]["desktop"]["height"] for key in HEIGHT_BEFORE}
    assert set(HEIGHT_BEFORE) == set(paper_keys(ROOT))
    over = {k: f"{h} px = {100 * h / HEIGHT_BEFORE[k]:.1f} %" for k, h in heights.items()
            if h > 0.4 * HEIGHT_BEFORE[k]}
    assert not over, over


def test_the_largest_page_loads_in_under_3_s(layout: dict[str, Any]) -> None:
    largest = layout["_largest"]
    assert largest["load"] < 3.0, largest


def _visible(page: Any, selector: str) -> bool:
    return page.evaluate(
        """sel => [...document.querySelectorAll(sel)].some(e => {
             const r = e.getBoundingClientRect(), s = getComputedStyle(e);
             return r.width > 0 && r.height > 0 && s.visibility !== 'hidden'
                    && r.right > 0 && r.left < innerWidth; })""",
        selector,
    )


@pytest.mark.parametrize("width", list(WIDTHS))
def test_menus_open_and_close(browser_context: Any, server: str, width: str) -> None:
    """The navigation (and on a phone the page's contents) open and close from their buttons."""
    w, h = WIDTHS[width]
    page = browser_context.new_page()
    page.set_viewport_size({"width": w, "height": h})
    page.goto(f"{server}/papers/lee2020.html", wait_until="load")
    nav, toc = ".bd-sidebar-primary .bd-links", ".bd-sidebar-secondary .bd-toc-nav"
    searches = page.evaluate(
        """() => [...document.querySelectorAll('.bd-search, .search-button-field, .search-button')]
             .filter(e => e.getBoundingClientRect().width > 0 && e.offsetParent !== null).length"""
    )
    assert searches == 1, f"{width}: {searches} search boxes in view"

    def toggle(selector: str) -> None:
        buttons = [b for b in page.query_selector_all(selector) if b.is_visible()]
        assert len(buttons) == 1, f"{width}: {len(buttons)} visible {selector}"
        buttons[0].click()
        page.wait_for_timeout(400)

    if width == "desktop":
        assert _visible(page, nav) and _visible(page, toc)
        toggle(".primary-toggle")
        assert not _visible(page, nav), "the menu button does not collapse the sidebar"
        toggle(".primary-toggle")
        assert _visible(page, nav), "the menu button does not bring the sidebar back"
    else:
        for button, panel in ((".primary-toggle", nav), (".secondary-toggle", toc)):
            assert not _visible(page, panel), f"{panel} shown before its button is pressed"
            toggle(button)
            assert _visible(page, panel), f"{button} does not open {panel}"
            # a tap beside the drawer (on the overlay) closes it
            page.mouse.click(w - 5 if "primary" in button else 5, h // 2)
            page.wait_for_timeout(400)
            assert not _visible(page, panel), f"{panel} does not close"
    assert _visible(page, ".fa-bars, .fa-list, .fa-solid"), "icons are not drawn"
    page.close()


READER_SHOTS = SHOTS / "reader"


def _reader_shot(page: Any, name: str, saved: list[Path]) -> None:
    page.wait_for_timeout(300)  # lazy images and maths in view are drawn
    path = READER_SHOTS / f"{name}.png"
    page.screenshot(path=str(path))
    saved.append(path)


def test_screenshots_of_what_a_reader_sees(browser_context: Any, server: str, site: Path) -> None:
    """Each paper page at 1280 and 390 px: its first two screens, its claims table, a folded code
    cell and the same cell unfolded, saved to build/site-screenshots/reader/ for people to look at."""
    READER_SHOTS.mkdir(parents=True, exist_ok=True)
    for old in READER_SHOTS.glob("*.png"):
        old.unlink()
    saved: list[Path] = []
    for w, h in WIDTHS.values():
        page = browser_context.new_page()
        page.set_viewport_size({"width": w, "height": h})
        for key in paper_keys(ROOT):
            page.goto(f"{server}/papers/{key}.html", wait_until="load")
            page.evaluate("async () => { if (window.MathJax) await MathJax.startup.promise; }")
            for screen in (0, 1):
                page.evaluate(f"window.scrollTo(0, {screen * h})")
                _reader_shot(page, f"{key}-{w}-screen{screen + 1}", saved)
            page.locator("table.secest-claims").scroll_into_view_if_needed()
            _reader_shot(page, f"{key}-{w}-claims", saved)
            folded = page.locator("div.cell details.hide.above-input").nth(2)
            folded.scroll_into_view_if_needed()
            page.evaluate("window.scrollBy(0, -120)")
            assert not folded.evaluate("d => d.open"), key
            _reader_shot(page, f"{key}-{w}-folded", saved)
            folded.locator("summary").click()
            assert folded.evaluate("d => d.open"), f"{key}: a folded cell does not unfold"
            _reader_shot(page, f"{key}-{w}-unfolded", saved)
        page.close()
    assert len(saved) == 2 * 5 * len(paper_keys(ROOT))
    assert all(p.stat().st_size > 5_000 for p in saved)


def test_plain_text_maths_is_typeset_and_code_left_alone() -> None:
    from secest.repro.site import ascii_maths, escape_md_typeset, sub_sup, typeset_markdown

    assert sub_sup("S̃_{1i,k+1} and y_k^{a,i}") == "S̃<sub>1i,k+1</sub> and y<sub>k</sub><sup>a,i</sup>"
    assert sub_sup("Σ_{j∈N_i∪{i}}") == "Σ<sub>j∈N<sub>i</sub>∪{i}</sub>"
    assert sub_sup("lemma_seed 7, x0_spread") == "lemma_seed 7, x0_spread"  # words, not indices
    assert ascii_maths("tr Gamma+ and +-2 sqrt(P_bar)") == "tr Γ⁺ and ±2 √(P̄)"
    assert ascii_maths("max_k |x_hat_B(1)| <= 1") == "max<sub>k</sub> |x̂<sub>B</sub>(1)| ≤ 1"
    assert ascii_maths("gamma0_scale `kappa` $x_1$") == "gamma0_scale `kappa` $x_1$"
    assert escape_md_typeset("a*b_{i}") == "a\\*b<sub>i</sub>"
    assert typeset_markdown("P̄* (not P̄_{k}), φ*/φ_*, *A second machine*, `a_{b}`, **C1**") == (
        "P̄<sup>∗</sup> (not P̄<sub>k</sub>), φ<sup>∗</sup>/φ<sub>∗</sub>, *A second machine*, "
        "`a_{b}`, **C1**"
    )
    assert typeset_markdown("are *not* a reason") == "are *not* a reason"


def test_errata_page_shows_no_raw_indices(site: Path) -> None:
    text = re.sub(r"<(pre|code)[^>]*>.*?</\1>", "", (site / "errata.html").read_text(), flags=re.S)
    text = re.sub(r"<[^>]+>", "", text)
    raw = re.findall(r".{0,20}[_^]\{.{0,20}", text)
    assert not raw, raw[:10]
    assert (site / "errata.html").read_text().count("<sub>") > 20
