"""No number in prose that the computation does not produce.

Every number in a Markdown cell of a notebook, and in the README and the
manual's pages of prose (website/*.md: PAGES) outside
code blocks and the tables written from data/, must be either an input the
text names (a problem parameter, a step, a tolerance, a constant of the
theory: INPUTS; an equation, section, figure or year reference; a small
integer used as an order, exponent, index, status or count: -12 to 12) or a value
that appears, to its printed digits, in the outputs of that notebook (of
any notebook, for the README) or in a summary file of data/ (time series,
whose thousands of values would match almost any number, do not count).
"""

import html
import json
import math
import re
from pathlib import Path

import jupytext
import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.py"))

# The inputs the texts name: the report's parameters (mu, spans, steps,
# initial values, the 1e-3 bound), the runs' settings (tolerances, the
# long run's span, the fit floor, the arcs' radii, step counts) and the
# constants of the closed forms (x^2/24; RK4's 72 and 576; the step range),
# and the Python version the environment pins.
INPUTS = [3.11, 0.4, 0.5, 0.6, 1.0, 50, 0.01, 0.016, 80, 800, 0.08, 6.25e-4, 1e-3, 1e-10, 1e-12,
          1e-13, 1e-14, 1e-2, 400, 24, 72, 576, 1.5, 4.5, 20, 200,
          # notebooks 07 and 09: the eccentric orbit, the Bratu guesses, tolerances, the long run
          0.9, 0.1, 1e-6, 1e-8, 1e-11, 300,
          # notebooks 08 and 10: samples per sampled orbit of the long runs
          64]
REFERENCE = re.compile(r"(?:eqs?\.|Secs?\.|Section|Figs?\.|Figure|Ch\.|Sec|issue #)\s*\d+[a-z]?"
                       r"(?:\s*[-,]\s*\d+[a-z]?)*|\b(?:19|20)\d\d\b|\b\d\d_\w+")
SCIENTIFIC = re.compile(r"(\d+(?:\.\d+)?)\s*\\times\s*10\^\{?(-?\d+)\}?")
POWER = re.compile(r"(?<![\d.])10\^\{?(-?\d+)\}?")
NUMBER = re.compile(r"(?<![\w.\\^_{])(-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)(%?)(?![\w])")


_SUPERSCRIPT_DIGITS = str.maketrans("\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079",
                                    "-0123456789")
# Printed lines write powers as plain text (scripts/outputs.plain): 7.2 × 10⁻⁶.
PLAIN_POWER = re.compile("(\\d+(?:\\.\\d+)?) \u00d7 10([\u207b\u2070\u00b9\u00b2\u00b3\u2074-\u2079]+)")


def _as_latex(match):
    exponent = match.group(2).translate(_SUPERSCRIPT_DIGITS)
    return f"{match.group(1)} \\times 10^{{{exponent}}}"


def numbers_in(text):
    """(value, significant digits, as written) for each number in ``text``."""
    text = PLAIN_POWER.sub(_as_latex, text)
    text = REFERENCE.sub(" ", text)
    found = []
    for match in SCIENTIFIC.finditer(text):
        mantissa, exponent = match.groups()
        digits = len(mantissa.replace(".", "").lstrip("0"))
        found.append((float(mantissa) * 10.0 ** int(exponent), digits, match.group(0)))
    text = SCIENTIFIC.sub(" ", text)
    for match in POWER.finditer(text):
        found.append((10.0 ** int(match.group(1)), 1, match.group(0)))
    text = POWER.sub(" ", text)
    for match in NUMBER.finditer(text):
        literal, percent = match.groups()
        mantissa = literal.split("e")[0].lstrip("-")
        digits = len(mantissa.replace(".", "").lstrip("0").rstrip("0") if "." not in mantissa
                     else mantissa.replace(".", "").lstrip("0")) or 1
        value = float(literal) / (100.0 if percent else 1.0)
        found.append((value, digits, match.group(0)))
    return found


def rounds_to(candidates, value, digits):
    """True if some candidate rounds to ``value`` at ``digits`` significant digits."""
    c = candidates[np.isfinite(candidates) & (candidates != 0)]
    if value == 0:
        return bool(np.any(candidates == 0))
    exponent = np.floor(np.log10(np.abs(c)))
    unit = 10.0 ** (exponent - digits + 1)
    rounded = np.round(c / unit) * unit
    return bool(np.any(np.abs(rounded - value) <= 1e-9 * abs(value)))


def unexplained(text, candidates):
    """The numbers of ``text`` that are neither inputs nor computed."""
    bad = []
    for value, digits, written in numbers_in(text):
        if float(value).is_integer() and abs(value) <= 12:
            continue
        if any(math.isclose(value, v, rel_tol=1e-12) for v in INPUTS):
            continue
        if not rounds_to(candidates, value, digits):
            bad.append(written)
    return bad


def output_numbers(ipynb):
    texts = []
    for cell in json.loads(ipynb.read_text())["cells"]:
        for out in cell.get("outputs", []):
            texts.append("".join(out.get("text", "")))
            for key in ("text/plain", "text/markdown"):
                texts.append("".join(out.get("data", {}).get(key, "")))
            # a table shown as HTML: its text, as the reader sees it (cells apart)
            table = "".join(out.get("data", {}).get("text/html", ""))
            texts.append(html.unescape(re.sub(r"<[^>]+>", " ", re.sub(r"<style.*?</style>", " ",
                                                                     table, flags=re.S))))
    return [v for text in texts for v, _, _ in numbers_in(text)]


SUMMARY_ROWS = 120  # prose quotes summaries: time series (longer files) do not count
# Columns that make a file a time series, whatever its length.
TIME_AXES = {"t", "orbit"}


def data_numbers():
    values = []
    for path in sorted((ROOT / "data").glob("*.csv")):
        frame = pd.read_csv(path)
        if len(frame) > SUMMARY_ROWS or TIME_AXES & set(frame.columns):
            continue
        for column in frame.columns:
            if pd.api.types.is_numeric_dtype(frame[column]):
                values.extend(frame[column].to_numpy(float))
            else:
                for text in frame[column].astype(str):
                    values.extend(v for v, _, _ in numbers_in(text))
    return values


@pytest.fixture(scope="module")
def data_values():
    return data_numbers()


def markdown_cells(script):
    return [c.source for c in jupytext.read(script).cells if c.cell_type == "markdown"]


# The site's pages of prose; not the report in brief (the report's own
# numbers), the API reference (docstrings) or the speed page (bench output).
PAGES = ["README.md"] + [f"website/{name}.md" for name in
                         ("guide", "scipy", "step-size-check", "fast-path", "findings", "layout")]


def readme_prose(name="README.md"):
    text = (ROOT / name).read_text().split("## References")[0]  # not the bibliography
    text = re.sub(r"```.*?```", " ", text, flags=re.S)
    text = re.sub(r"<!-- begin (\w+) -->.*?<!-- end \1 -->", " ", text, flags=re.S)
    return re.sub(r"\]\([^)]*\)", "]", text)  # link targets are paths


@pytest.mark.parametrize("script", NOTEBOOKS, ids=lambda p: p.stem)
def test_every_number_in_a_notebook_is_an_input_or_computed(script, data_values):
    candidates = np.array(output_numbers(script.with_suffix(".ipynb")) + data_values)
    bad = {i: unexplained(text, candidates) for i, text in enumerate(markdown_cells(script))}
    assert not any(bad.values()), {i: b for i, b in bad.items() if b}


@pytest.mark.parametrize("name", PAGES)
def test_every_number_in_the_readme_and_manual_is_an_input_or_computed(name, data_values):
    outputs = [v for script in NOTEBOOKS for v in output_numbers(script.with_suffix(".ipynb"))]
    candidates = np.array(outputs + data_values)
    assert unexplained(readme_prose(name), candidates) == []


def test_a_planted_number_is_found(data_values):
    """The check fails when one number of a Markdown cell is changed."""
    script = ROOT / "notebooks" / "02_cannonball.py"
    candidates = np.array(output_numbers(script.with_suffix(".ipynb")) + data_values)
    cell = markdown_cells(script)[0]
    assert unexplained(cell, candidates) == []
    assert unexplained(cell.replace("\\Delta t = 0.01", "\\Delta t = 0.0137"), candidates) \
        == ["0.0137"]
    assert unexplained(cell + " The error reaches $4.67 \\times 10^{-3}$.", candidates) \
        == ["4.67 \\times 10^{-3}"]
    assert unexplained(cell + " The error reaches $4.1 \\times 10^{-3}$.", candidates) == []

