/* Readable at a laptop's width and a phone's (readable.css says how).

   1. Each code block and printed output is split into one element per line,
      so that a line too long for the block wraps with a hanging indent
      instead of running past the block's edge: printed text under its own
      indent plus two characters, code under its comment (or its indent
      plus four).
      A table printed in aligned columns (two lines or more with a run of
      spaces between words): each row breaks only between its columns, the
      columns after the break four characters in, so that every value stays
      in view; where the columns fit, the table is as printed.  A
      right-aligned table (pandas) too wide for its block loses the spaces
      that right-align it; a pretty-printed matrix never wraps (its block
      scrolls).
   2. A box that still scrolls sideways gets a shade at its right edge
      until it is scrolled to its end.
   3. A formula wider than the column scrolls (the theme cuts it off); a
      displayed one gets the shade of 2 as well.
   4. Each image of the text is a link to its file: a click opens the
      figure at full size.
   5. A long name in the sidebars (the API page's contents) may break
      after an underscore or a dot.
   6. Every sidebar button opens its sidebar (see toggles). */
(function () {
  "use strict";

  // A run of two or more spaces between two words (not after a full stop,
  // a comma, a colon or a parenthesis): aligned columns.
  const COLUMNS = /[^\s.;:,(] {2,}\S/;
  // Box drawing and bracket pieces (sympy's pretty-printed matrices).
  const DRAWING = /[\u2500-\u257f\u239b-\u23bf]/;
  // The continuation lines outputs.wrapped writes: two spaces in.
  const CONTINUED = /^ {2}\S/;
  // Pygments' comment tokens.
  const COMMENT = new Set(["c", "c1", "ch", "cm", "cs", "cpf"]);

  // The nodes of each line of a <pre> (pygments writes flat spans).
  function lines(pre) {
    const found = [[]];
    for (const node of Array.from(pre.childNodes)) {
      const text = node.textContent;
      if (!text) continue;
      if (!text.includes("\n")) {
        found[found.length - 1].push(node);
        continue;
      }
      text.split("\n").forEach(function (part, index) {
        if (index > 0) found.push([]);
        if (!part) return;
        let piece = document.createTextNode(part);
        if (node.nodeType === Node.ELEMENT_NODE && node.children.length === 0) {
          piece = node.cloneNode(false);
          piece.textContent = part;
        }
        found[found.length - 1].push(piece);
      });
    }
    if (found.length > 1 && found[found.length - 1].length === 0) found.pop();
    return found;
  }

  // The columns of a row, each in a span.ss-cell; the runs of spaces
  // between them stay text, where the row may break.
  function cells(span) {
    const walker = document.createTreeWalker(span, NodeFilter.SHOW_TEXT);
    const texts = [];
    while (walker.nextNode()) texts.push(walker.currentNode);
    for (const node of texts) {
      const parts = node.textContent.split(/( {2,})/);
      const fragment = document.createDocumentFragment();
      parts.forEach(function (part, index) {
        if (!part) return;
        if (index % 2 === 1) {
          fragment.append(document.createTextNode(part));
        } else {
          const cell = document.createElement("span");
          cell.className = "ss-cell";
          cell.textContent = part;
          fragment.append(cell);
        }
      });
      node.replaceWith(fragment);
    }
  }

  // The spaces that right-align a row, in a span.ss-lead: dropped where
  // the table is wider than its block.
  function lead(span) {
    const node = span.firstChild;
    if (!node || node.nodeType !== Node.TEXT_NODE) return;
    const spaces = node.textContent.match(/^\s+/);
    if (!spaces) return;
    const leading = document.createElement("span");
    leading.className = "ss-lead";
    leading.textContent = spaces[0];
    node.textContent = node.textContent.slice(spaces[0].length);
    span.insertBefore(leading, node);
  }

  function splitPre(pre) {
    if (pre.classList.contains("ss-lines")) return;
    const printed = !!pre.closest(".cell_output, .output, .ss-example-output");
    const nodes = lines(pre);
    const texts = nodes.map(function (line) {
      return line.map(function (n) { return n.textContent; }).join("");
    });
    // A table: two rows or more; the lines from its first row to its last
    // are its rows, but for continuation lines.
    const matched = texts.map(function (t) { return COLUMNS.test(t) || DRAWING.test(t); });
    const table = printed && matched.filter(Boolean).length >= 2;
    const first = matched.indexOf(true), last = matched.lastIndexOf(true);
    function row(index) {
      return table && index >= first && index <= last &&
        (matched[index] || !CONTINUED.test(texts[index]));
    }
    // Right-aligned: most rows start with spaces (not a continuation's two).
    const rows = texts.filter(function (t, index) { return row(index); });
    const rightAligned = rows.filter(function (t) {
      return /^\s/.test(t) && !CONTINUED.test(t);
    }).length * 2 > rows.length;
    const fragment = document.createDocumentFragment();
    nodes.forEach(function (line, index) {
      const text = texts[index];
      const span = document.createElement("span");
      span.className = "ss-line";
      span.append.apply(span, line);
      const indent = text.length - text.replace(/^\s+/, "").length;
      span.dataset.hang = String(indent + (printed ? 2 : 4));
      if (row(index) && DRAWING.test(text)) {
        span.classList.add("ss-row");
      } else if (row(index)) {
        span.classList.add("ss-cells");
        if (rightAligned) lead(span);
        cells(span);
        span.dataset.hang = String(rightAligned ? 4 : indent + 4);
      } else if (!printed) {
        // a comment after code: continuation lines under the comment
        let column = 0;
        for (const n of line) {
          if (n.nodeType === Node.ELEMENT_NODE && COMMENT.has(n.className) && column >= indent) {
            // under the comment's text, past its "# "
            const marker = n.textContent.match(/^(#|\/\/)\s*/);
            const text = column + (marker ? marker[0].length : 0);
            if (column > indent) span.dataset.comment = String(text);
            else span.dataset.hang = String(text);  // a line that is all comment
            break;
          }
          column += n.textContent.length;
        }
      }
      fragment.append(span);
    });
    pre.replaceChildren(fragment);
    pre.classList.add("ss-lines");
    hangs(pre);
  }

  // The hanging indent of each line, in characters, for the block's width:
  // a comment's column if that is in the block's left half, and never more
  // than half the block.
  function hangs(pre) {
    const style = getComputedStyle(pre);
    const width = pre.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight);
    if (width <= 0) return;  // not shown (a collapsed cell): when opened
    const probe = document.createElement("span");
    probe.style.cssText = "position: absolute; visibility: hidden; white-space: pre";
    probe.textContent = "0".repeat(20);
    pre.append(probe);
    const columns = width / (probe.getBoundingClientRect().width / 20);
    probe.remove();
    pre.classList.remove("ss-narrow");
    if (pre.querySelector(".ss-lead")) {
      const widest = Math.max.apply(null, Array.from(pre.children, function (line) {
        return line.textContent.length;
      }));
      pre.classList.toggle("ss-narrow", widest > columns);
    }
    for (const line of pre.children) {
      let hang = Number(line.dataset.hang);
      const comment = Number(line.dataset.comment || Infinity);
      if (comment <= columns / 2) hang = comment;
      line.style.setProperty("--ss-hang", String(Math.min(hang, Math.floor(columns / 2))));
    }
  }

  // A shade at the right edge of a box that scrolls, until its end is
  // shown: the box is put in a frame that draws it.
  function frame(box) {
    const outer = document.createElement("div");
    outer.className = "ss-frame";
    box.replaceWith(outer);
    outer.append(box);
    shade(box);
    box.addEventListener("scroll", function () { shade(box); }, {passive: true});
  }

  function shade(box) {
    const more = box.scrollWidth > box.clientWidth + 1 &&
      box.scrollLeft + box.clientWidth < box.scrollWidth - 1;
    box.parentElement.classList.toggle("ss-more", more);
  }

  // A formula wider than the column, which the theme would cut at the
  // column's edge, scrolls instead (a glyph's overhang of a few pixels in
  // a narrow formula stays as the theme has it).
  function wideMath() {
    const all = Array.from(document.querySelectorAll(".bd-article .math.notranslate"));
    all.forEach(function (math) { math.classList.remove("ss-wide-math"); });
    all.filter(function (math) {
      const parent = math.parentElement, style = getComputedStyle(parent);
      const column = parent.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight);
      // MathJax's own span.math inside, which the theme clips as well
      const typeset = math.querySelector("span.math") || math;
      const cut = Math.max(math.scrollWidth - math.clientWidth, typeset.scrollWidth - typeset.clientWidth);
      return cut > 1 && math.offsetWidth >= column - 2;
    }).forEach(function (math) { math.classList.add("ss-wide-math"); });
  }

  // A wide displayed formula: in a frame that shades its right edge while
  // there is more to scroll to, as a box of code.
  function frameMath() {
    document.querySelectorAll(".bd-article div.math.ss-wide-math").forEach(function (math) {
      if (math.parentElement.classList.contains("ss-frame")) {
        shade(math);
        return;
      }
      frame(math);
      math.parentElement.classList.add("ss-math-frame");
    });
    document.querySelectorAll(".bd-article .ss-math-frame > div.math:not(.ss-wide-math)")
      .forEach(shade);
  }

  // Long names in the sidebars (the API page's contents) may break after an
  // underscore or a dot.
  function breakNames() {
    const selector = ".bd-sidebar-primary code span.pre, .bd-sidebar-secondary code span.pre";
    document.querySelectorAll(selector).forEach(function (span) {
      if (span.querySelector("wbr") || !/[._]\w/.test(span.textContent)) return;
      const parts = span.textContent.split(/(?<=[._])(?=\w)/);
      span.replaceChildren();
      parts.forEach(function (part, index) {
        if (index > 0) span.append(document.createElement("wbr"));
        span.append(document.createTextNode(part));
      });
    });
  }

  function afterMath() {
    if (window.MathJax && MathJax.Hub && MathJax.Hub.Register) {
      MathJax.Hub.Register.StartupHook("End", function () {
        MathJax.Hub.Queue(wideMath, frameMath);
      });
    } else {
      wideMath();
      frameMath();
    }
  }

  function linkImages() {
    for (const img of document.querySelectorAll(".bd-article img")) {
      if (img.closest("a")) continue;
      const src = img.getAttribute("src");
      if (!src || src.startsWith("data:")) continue;
      const link = document.createElement("a");
      link.href = src;
      link.className = "ss-image-link";
      link.title = "Open the figure at full size";
      img.replaceWith(link);
      link.append(img);
    }
  }

  function start() {
    breakNames();
    document.querySelectorAll(".bd-article pre").forEach(splitPre);
    linkImages();
    document.querySelectorAll(".bd-article pre, .bd-article .pst-scrollable-table-container, " +
                              ".bd-article .cell_output > .output.text_html").forEach(frame);
    if (document.readyState === "complete") afterMath();
    else window.addEventListener("load", afterMath);
    let pending = false;
    window.addEventListener("resize", function () {
      if (pending) return;
      pending = true;
      window.requestAnimationFrame(function () {
        pending = false;
        document.querySelectorAll(".bd-article pre.ss-lines").forEach(hangs);
        wideMath();
        frameMath();
        document.querySelectorAll(".bd-article .ss-frame > *").forEach(shade);
      });
    });
    // a collapsed code cell opened: its lines' indents, its shade
    document.addEventListener("toggle", function (event) {
      event.target.querySelectorAll("pre.ss-lines").forEach(function (pre) {
        hangs(pre);
        shade(pre);
      });
    }, true);
  }

  // 6. The theme binds its sidebar buttons (the menu and the page's
  //    contents) by the first element of each class, which the book
  //    theme's header hides; the visible ones then do nothing.  Each other
  //    button of the class passes its click to the first.
  function toggles() {
    [".primary-toggle", ".secondary-toggle"].forEach(function (kind) {
      const buttons = document.querySelectorAll(kind);
      buttons.forEach(function (button, index) {
        if (index === 0) return;
        button.addEventListener("click", function (event) {
          event.preventDefault();
          event.stopPropagation();
          buttons[0].click();
        });
      });
    });
  }

  function begin() {
    start();
    toggles();
  }

  if (document.readyState === "loading") {
    document.addEventListener("DOMContentLoaded", begin);
  } else {
    begin();
  }
})();
