"""Printed lines of the notebooks: scripts/outputs.wrapped breaks a long
measured line where a reader expects it, not where the pane ends."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import outputs  # noqa: E402


def test_wrapped_breaks_long_lines_at_clauses_then_spaces_and_keeps_every_word():
    text = ("spline, order 2    1673 evaluations per orbit; energy error 4.2 × 10⁻⁴ in the "
            "first orbit, 4.2 × 10⁻⁴ in orbit 10000 (growth exponent -0.00); position error "
            + "and a clause long enough to need a break at a space " * 3)
    out = outputs.wrapped(text, width=80)
    lines = out.split("\n")
    assert all(len(line) <= 80 for line in lines)
    assert lines[0] == "spline, order 2    1673 evaluations per orbit;"
    assert all(line.startswith("  ") for line in lines[1:])
    assert out.split() == text.split()
    assert outputs.wrapped("short; line") == "short; line"


def test_no_notebook_prints_a_line_wider_than_its_pane():
    """JupyterLab at 1366 x 900 shows about 115 characters of a printed line
    before it breaks it wherever the pane ends."""
    import json
    root = Path(__file__).resolve().parents[1]
    wide = []
    for path in sorted((root / "notebooks").glob("*.ipynb")):
        for cell in json.loads(path.read_text())["cells"]:
            for output in cell.get("outputs", []):
                if output.get("output_type") == "stream":
                    wide += [(path.name, line) for line in "".join(output["text"]).splitlines()
                             if len(line) > 110]
    assert not wide, wide
