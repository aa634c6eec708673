"""How the API reference reads the package's docstrings.

The docstrings are numpydoc, written to be read in ``help()``: plain-text
formulas such as ``|y|``, ``y'' = fun(t, y, y', *args)`` and numbered
references ``.. [1]``.  :func:`as_rst` is Sphinx's
``autodoc-process-docstring`` hook (``conf.py``): it escapes the characters
that reStructuredText would read as markup outside literal text (``|`` as a
substitution, a lone ``*`` as emphasis) and gives each docstring's numbered
references labels of their own, so that two docstrings on one page may
both cite their ``[1]``: ``[1]`` of ``splinestep.solve`` becomes the
citation ``[solve-1]``, which Sphinx resolves on the page wherever the
docstring's fields put it.  The docstrings themselves are not changed.
"""

import re

# Inline literals (``...``) and roles (:func:`...`) are left as written.
_LITERAL = re.compile(r"(``.*?``|:\w+:`[^`]*`)")
_FOOTNOTE = re.compile(r"(\.\. \[|\[)(\d+)(\]_?)")


def _escaped(text):
    """``text`` with | and a lone * escaped, outside inline literals."""
    parts = _LITERAL.split(text)
    for index in range(0, len(parts), 2):
        part = parts[index].replace("|", "\\|")
        parts[index] = re.sub(r"(?<![*\\])\*(?!\*)", r"\\*", part)
    return "".join(parts)


def as_rst(app, what, name, obj, options, lines):
    """Sphinx's autodoc-process-docstring: the docstring of ``name``, as
    lines of reStructuredText (changed in place)."""
    label = name.removeprefix("splinestep.")
    literal_block, indent = False, 0
    for index, line in enumerate(lines):
        stripped = line.lstrip()
        depth = len(line) - len(stripped)
        if literal_block and stripped and depth <= indent:
            literal_block = False
        if not literal_block:
            line = _escaped(line)
            line = _FOOTNOTE.sub(lambda m: f"{m.group(1)}{label}-{m.group(2)}{m.group(3)}"
                                 if m.group(1) == ".. [" or m.group(3) == "]_" else m.group(0), line)
            if stripped.endswith("::") and not stripped.startswith(".."):
                literal_block, indent = True, depth
        lines[index] = line
