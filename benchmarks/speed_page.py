"""The site's Speed page, website/speed.md, into which each benchmark writes
its tables between a pair of markers of its own."""

import re
from pathlib import Path

PAGE = Path(__file__).resolve().parent.parent / "website" / "speed.md"


def write_section(name, text):
    """Replace what stands between ``<!-- begin name -->`` and ``<!-- end
    name -->`` in the Speed page with ``text``."""
    old = PAGE.read_text()
    new = re.sub(rf"(<!-- begin {name} -->\n).*?(<!-- end {name} -->)",
                 lambda match: match.group(1) + text + "\n" + match.group(2), old, flags=re.S)
    PAGE.write_text(new)
