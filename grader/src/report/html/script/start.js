  // The start: each inspector built when its case comes near the screen,
  // the static pictures on demand; the end of the scope model.js opens.

  // The static pictures sit in a <noscript> (a page with script parses
  // none of their thousands of paths): shown on demand from its text.
  function showStatic(root) {
    var section = root.closest('section'), ns = section && section.querySelector('noscript');
    if (!ns || ns.meshlabShown) { return; }
    ns.meshlabShown = true;
    var div = document.createElement('div');
    div.innerHTML = ns.textContent;
    ns.parentNode.insertBefore(div, ns.nextSibling);
  }

  // Each inspector is built when its case comes near the screen (a page
  // of every case would take seconds to build at once); tests and links
  // build one at once with window.meshlabInspect(name).
  function start() {
    var all = {}, roots = {};
    var canvas = document.createElement('canvas');
    if (!canvas.getContext || !canvas.getContext('2d')) { return; }
    var build = function (root) {
      if (root.meshlabBuilt) { return all[root.meshlabName]; }
      root.meshlabBuilt = true;
      var blob = root.querySelector('script.inspector-data');
      try {
        var data = JSON.parse(blob.textContent);
        var insp = new Inspector(root, data);
        all[data.name] = insp;
        return insp;
      } catch (e) {
        root.setAttribute('hidden', '');
        var p = document.createElement('p');
        p.className = 'inspector-failed';
        p.textContent = 'the inspector could not show this case (' + e + '); the static pictures below still do';
        root.parentNode.insertBefore(p, root);
        showStatic(root);
        if (window.console) { console.error(e); }
        return null;
      }
    };
    var observer = window.IntersectionObserver ? new IntersectionObserver(function (entries) {
      entries.forEach(function (en) { if (en.isIntersecting) { observer.unobserve(en.target); build(en.target); } });
    }, { rootMargin: '300px' }) : null;
    Array.prototype.forEach.call(document.querySelectorAll('div.inspector'), function (root) {
      var section = root.closest('section');
      var name = section ? section.getAttribute('data-case') : null;
      root.meshlabName = name;
      roots[name] = root;
      // Until it is built, the inspector holds its place.
      root.removeAttribute('hidden');
      root.classList.add('pending');
      if (observer) { observer.observe(root); } else { build(root); }
    });
    window.meshlabInspectors = all;
    window.meshlabInspect = function (name) { return roots[name] ? build(roots[name]) : null; };
    // When the page was ready to use, for the tests' measurement.
    document.documentElement.setAttribute('data-inspector-ready', String(Math.round(performance.now())));
  }
  if (document.readyState === 'loading') { document.addEventListener('DOMContentLoaded', start); } else { start(); }
})();
