// A link to a section whose rest is folded (the end matter of a notebook page, see
// docs/_ext/secest_sphinx.py) opens that section, so the reader lands on what the link promised
// (ERRATA's links land on "Deviations from the paper") and its heading can reach the top.
(function () {
  function openTarget() {
    const id = decodeURIComponent(window.location.hash.slice(1));
    const target = id && document.getElementById(id);
    if (!target) return;
    let opened = false;
    for (let s = target.closest("section"); s; s = s.parentElement && s.parentElement.closest("section")) {
      const box = s.querySelector(":scope > details.secest-section-more");
      if (box && !box.open) { box.open = true; opened = true; }
    }
    if (opened) target.scrollIntoView();
  }
  window.addEventListener("hashchange", openTarget);
  document.addEventListener("DOMContentLoaded", openTarget);
})();
