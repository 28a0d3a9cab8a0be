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

// Re-typeset after instant navigation (mkdocs-material's document$ observable).
if (typeof document$ !== "undefined") {
  document$.subscribe(() => {
    if (!(window.MathJax && MathJax.startup && MathJax.startup.output)) return; // first load: MathJax typesets on startup
    MathJax.startup.output.clearCache();
    MathJax.typesetClear();
    MathJax.texReset();
    MathJax.typesetPromise();
  });
}
