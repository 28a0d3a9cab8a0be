// MathJax configuration for pymdownx.arithmatex (generic mode); MathJax itself is served from
// javascripts/mathjax/ (vendored, see README.txt there), so no network is needed.
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"]],
    displayMath: [["\\[", "\\]"]],
    processEscapes: true,
    processEnvironments: true
  },
  options: {
    ignoreHtmlClass: ".*|",
    processHtmlClass: "arithmatex",
    // the menu's speech and explorer options would fetch their engine from a CDN: the site works offline
    enableMenu: false
  }
};

// Re-typeset after instant navigation (mkdocs-material's document$ observable). Its first
// emission is the page as loaded, which MathJax typesets on startup by itself: re-typesetting it
// (clearing the output's cache) would drop the glyphs' styles when MathJax, served locally, is
// already running by then.
if (typeof document$ !== "undefined") {
  let loaded = false;
  document$.subscribe(() => {
    if (!loaded) {
      loaded = true;
      return;
    }
    if (!(window.MathJax && MathJax.startup && MathJax.startup.output)) return;
    MathJax.startup.output.clearCache();
    MathJax.typesetClear();
    MathJax.texReset();
    MathJax.typesetPromise();
  });
}
