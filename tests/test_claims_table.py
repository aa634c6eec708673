"""The claims table of notebook 14 (scripts/claims.py): every claim points
at a section that exists, and the count of verdicts adds up."""

import re
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import claims  # noqa: E402

TABLE = pd.read_csv(ROOT / "data" / "claims.csv")


def headings(notebook):
    """The Markdown headings of notebooks/NOTEBOOK.py as plain text: without
    the #s, a leading number ("2. ") or the $ of inline math."""
    text = (ROOT / "notebooks" / f"{notebook}.py").read_text()
    return [re.sub(r"^\d+\. ", "", m.group(1)).replace("$", "")
            for m in re.finditer(r"^# #+ (.+)$", text, flags=re.MULTILINE)]


@pytest.mark.parametrize("notebook, section", sorted(set(zip(TABLE.notebook, TABLE.section))))
def test_each_claim_links_to_a_heading_of_its_notebook(notebook, section):
    assert any(h.startswith(section) for h in headings(notebook)), (notebook, section)


def test_one_function_per_row_and_known_kinds():
    assert len(TABLE) == len(claims.CLAIMS)
    assert set(TABLE.kind) <= set(claims.KINDS)
    with pytest.raises(ValueError, match="kind"):
        claims.row("Sec. 1", "a claim", "measured", "verdict", "confirmed", "01_method", "x")


def test_summary_counts_every_claim_once():
    line = claims.summary(TABLE.kind)
    kinds = "|".join(map(re.escape, claims.KINDS))
    counts = [int(n) for n in re.findall(rf"(\d+) (?:{kinds})", line)]
    assert sum(counts) == len(TABLE) == int(line.split()[0])
