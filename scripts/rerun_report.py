"""What a ``make reproduce`` run wrote, against the committed files.

Every file the run rewrote (the notebooks' data tables, figures and
``.ipynb`` files, the paper, the README's tables) is compared with its
version in git HEAD (``git cat-file``), by the rules ``make test`` applies
(``tests/reproduction.py``): a data table column by column at its kind's
tolerance (:func:`reproduction.compare_frames`), a figure by its PNG
(:func:`reproduction.figures_match`; its PDF is drawn from the same data),
a notebook by its printed text after the sanitize rules nbval uses
(:func:`reproduction.notebook_difference`).  The paper is built from the data
and figures: it is said to be identical or rebuilt from them, not judged.
A few lines per kind say how many files are identical, how many within
tolerance (with the largest difference), and name those beyond.

:func:`report` returns the exit status of ``make reproduce``: 0 when every
file is identical or within tolerance (or when there is no git checkout to
compare with); :data:`NOT_REPRODUCED` when a file is beyond tolerance while
the sources the outputs are made from (:data:`SOURCES`) are HEAD's: a
failed reproduction.  When those sources are edited, outputs that differ
are the edit's result, not a failed reproduction: they are named, the
status stays 0.  The files are left as written either way.
"""

import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "tests") not in sys.path:
    sys.path.append(str(ROOT / "tests"))  # reproduction.py: the rules of `make test`

# Exit status of `make reproduce` when an output is beyond tolerance.
NOT_REPRODUCED = 3
# What the outputs are made from, as git pathspecs: edited, outputs may differ.
SOURCES = ("src", "notebooks/*.py", "scripts", "pyproject.toml", "environment.txt")
# Below this relative difference, only the last digits of a value moved.
LAST_DIGITS = 1e-9
# Lines naming files beyond tolerance, at most, per kind.
NAMED = 6


class NoCheckout(Exception):
    """No committed version to compare with (no git, or not a checkout)."""


def _git(root, *args, stdin=None):
    try:
        done = subprocess.run(["git", "-C", str(root), *args], input=stdin,
                              capture_output=True, check=False)
    except FileNotFoundError:
        raise NoCheckout("git is not installed") from None
    if done.returncode:
        reason = (done.stderr.decode(errors="replace").strip().splitlines() or ["?"])[0]
        raise NoCheckout(f"{root} is not a git checkout with a commit ({reason})")
    return done.stdout


def committed_versions(paths, root=ROOT):
    """{path relative to ``root``: its bytes in git HEAD, or None where HEAD
    has no such file}, read by one ``git cat-file --batch``."""
    _git(root, "rev-parse", "--verify", "--quiet", "HEAD^{commit}")
    names = [Path(p).resolve().relative_to(Path(root).resolve()).as_posix() for p in paths]
    out = _git(root, "cat-file", "--batch",
               stdin="".join(f"HEAD:{name}\n" for name in names).encode())
    found, at = {}, 0
    for name in names:
        end = out.index(b"\n", at)
        header = out[at:end].split()
        if header[-1] == b"missing":
            found[name], at = None, end + 1
            continue
        size = int(header[2])
        found[name], at = out[end + 1:end + 1 + size], end + 2 + size
    return found


def edited_sources(root=ROOT):
    """The tracked files of :data:`SOURCES` that differ from HEAD's."""
    out = _git(root, "status", "--porcelain", "--untracked-files=no", "--", *SOURCES)
    return [line[3:] for line in out.decode().splitlines()]


@dataclass
class Verdict:
    """One output: its ``kind`` (data, figures, notebooks, paper), ``name``,
    ``status`` (identical, within, beyond, new) and what to say of it:
    ``detail`` (a phrase) and ``size`` (to find the largest difference)."""
    kind: str
    name: str
    status: str
    detail: str = ""
    size: float = 0.0


def largest_difference(name, old, new):
    """(relative difference, where, kind) of the value of ``new`` (a frame of
    ``data/<name>.csv``) that moved most from ``old``'s, relative to its size,
    among values above the rounding floor; None if none moved."""
    import numpy as np
    import pandas as pd
    import reproduction
    best = None
    for column in old.columns:
        if not (pd.api.types.is_numeric_dtype(old[column])
                and pd.api.types.is_numeric_dtype(new[column])):
            continue
        a, b = old[column].to_numpy(float), new[column].to_numpy(float)
        size = np.maximum(np.abs(a), np.abs(b))
        with np.errstate(divide="ignore", invalid="ignore"):
            relative = np.abs(b - a) / size
        relative[~(size > reproduction.ROUNDING_FLOOR) | ~np.isfinite(relative)] = 0.0
        row = int(np.argmax(relative)) if relative.size else 0
        if relative.size and relative[row] > (best[0] if best else 0.0):
            kind = reproduction.row_kinds(name, old, column)[row]
            best = (float(relative[row]), f"{column}[{row}]", kind)
    return best


def compare_data(path, old_bytes):
    """The :class:`Verdict` on the data table ``path`` against ``old_bytes``."""
    import io
    import pandas as pd
    import reproduction
    path = Path(path)
    old, new = pd.read_csv(io.BytesIO(old_bytes)), pd.read_csv(path)
    try:
        problems = reproduction.compare_frames(path.stem, old, new)
    except KeyError as error:  # a column without a declared kind
        problems = [error.args[0]]
    if problems:
        return Verdict("data", path.name, "beyond", first_cell(path, old, new) or problems[0])
    moved = largest_difference(path.stem, old, new)
    if moved is None:
        return Verdict("data", path.name, "within", "the same values, written differently")
    relative, where, kind = moved
    return Verdict("data", path.name, "within",
                   f"largest relative difference {relative:.1e} in {path.name} {where} ({kind})",
                   relative)


def first_cell(path, old, new):
    """The first value of the table ``path`` (frame ``new``) that does not
    reproduce ``old``'s, named with its column, row and kind, and how many
    do not; None when the columns or the shape differ."""
    import reproduction
    if list(old.columns) != list(new.columns) or old.shape != new.shape:
        return None
    found, count = None, 0
    for column in old.columns:
        kinds, differ = reproduction.differing_rows(path.stem, old, new, column)
        count += int(differ.sum())
        if found is None and differ.any():
            row = int(differ.argmax())
            found = (f"{path.name} {column}[{row}] ({kinds[row]}): "
                     + excerpt(old[column].iloc[row], new[column].iloc[row]))
    return found + (f" ({count - 1} more)" if count > 1 else "")


def excerpt(old, new, width=18):
    """``old -> new``, for text a window of ``width`` characters of each
    around where they start to differ."""
    old, new = (getattr(v, "item", lambda v=v: v)() for v in (old, new))
    if not (isinstance(old, str) and isinstance(new, str)):
        return f"{old!r} -> {new!r}"
    at = next((i for i, (a, b) in enumerate(zip(old, new)) if a != b), min(len(old), len(new)))
    start = max(0, min(at - width // 3, max(len(old), len(new)) - width))
    cut = [("..." if start else "") + text[start:start + width]
           + ("..." if len(text) > start + width else "") for text in (old, new)]
    return f"{cut[0]!r} -> {cut[1]!r}"


def compare_figure(stem, files):
    """The :class:`Verdict` on one figure from ``files``: {suffix: (committed
    bytes or None, path written)}; judged by its PNG under the rule of
    :func:`reproduction.figures_match`, its PDF drawn from the same data."""
    import reproduction
    name = stem + "".join(sorted(files))
    if all(new.read_bytes() == old for old, new in files.values()):
        return Verdict("figures", name, "identical")
    if ".png" not in files:
        return Verdict("figures", name, "unjudged", "a PDF without a PNG to judge it by")
    old, new = files[".png"]
    if old is None:
        return Verdict("figures", name, "new")
    if new.read_bytes() == old:
        return Verdict("figures", name, "within", f"{stem}.png identical, its PDF redrawn")
    with tempfile.TemporaryDirectory() as folder:
        committed = Path(folder) / f"{stem}.png"  # the name sets the shift allowed
        committed.write_bytes(old)
        unmatched = reproduction.unmatched_both_ways(committed, new)
    if unmatched is None:
        return Verdict("figures", name, "beyond", f"{stem}.png: another size in pixels")
    shift = reproduction.FIGURE_SHIFTS.get(stem, reproduction.FIGURE_SHIFT)
    allowed = reproduction.FIGURE_PIXELS
    if unmatched > allowed:
        return Verdict("figures", name, "beyond", f"{stem}.png: {unmatched} pixels without "
                       f"a match within {shift} px ({allowed} allowed)")
    if unmatched == 0:
        return Verdict("figures", name, "within", "every changed pixel has a match within "
                       f"{shift} px ({stem}.png)", 0.5)
    return Verdict("figures", name, "within", f"{unmatched} pixels (of {allowed} allowed) "
                   f"without a match within {shift} px, in {stem}.png", unmatched)


def compare_notebook(path, old_bytes, patterns):
    """The :class:`Verdict` on a written notebook against ``old_bytes``."""
    import reproduction
    path = Path(path)
    difference = reproduction.notebook_difference(old_bytes.decode(), path.read_text(),
                                                  patterns)
    if difference is None:
        return Verdict("notebooks", path.name, "within")
    where, old, new = difference
    return Verdict("notebooks", path.name, "beyond", f"{path.name} {where}: {excerpt(old, new)}")


def kind_of_output(name):
    """data, figures, notebooks, paper or None (not compared) for a path
    relative to the repository."""
    folder, _, file = name.rpartition("/")
    suffix = Path(file).suffix
    if folder == "data" and suffix == ".csv":
        return "data"
    if folder == "figures" and suffix in (".png", ".pdf"):
        return "figures"
    if folder == "notebooks" and suffix == ".ipynb":
        return "notebooks"
    if name == "paper/splinestep.pdf":
        return "paper"
    return None


def verdicts(committed, root=ROOT):
    """A :class:`Verdict` for each output in ``committed`` ({path relative
    to ``root``: HEAD's bytes or None}); files of no compared kind left out."""
    import reproduction
    found, figures, patterns = [], {}, None
    for name, old in sorted(committed.items()):
        kind, path = kind_of_output(name), Path(root) / name
        if kind is None:
            continue
        if kind == "figures":
            figures.setdefault(path.stem, {})[path.suffix] = (old, path)
        elif old is None:
            found.append(Verdict(kind, path.name, "new"))
        elif path.read_bytes() == old:
            found.append(Verdict(kind, path.name, "identical"))
        elif kind == "data":
            found.append(compare_data(path, old))
        elif kind == "notebooks":
            patterns = patterns or reproduction.nbval_sanitize_patterns()
            found.append(compare_notebook(path, old, patterns))
        else:
            found.append(Verdict(kind, path.name, "rebuilt"))
    return found + [compare_figure(stem, files) for stem, files in sorted(figures.items())]


# What the lines say of each kind: its name, and what precedes the detail of
# the file within tolerance that differs most (a notebook's: the same text).
KINDS = {"data": ("data tables", ""),
         "figures": ("figures", ""),
         "notebooks": ("notebooks", "same printed text after tests/nbval-sanitize.cfg; "
                                    "images, metadata differ")}


def summary(found):
    """The lines that say what ``found`` (Verdicts) holds, a few per kind."""
    lines = []
    for kind, (title, within) in KINDS.items():
        mine = [v for v in found if v.kind == kind]
        if not mine:
            continue
        counts = {s: sum(v.status == s for v in mine)
                  for s in ("identical", "within", "beyond", "new", "unjudged")}
        lines.append(f"{title}: {len(mine)} written, {counts['identical']} identical, "
                     f"{counts['within']} within tolerance, {counts['beyond']} beyond"
                     + "".join(f", {counts[s]} {s}" for s in ("new", "unjudged") if counts[s]))
        close = [v for v in mine if v.status == "within"]
        if close:
            worst = max(close, key=lambda v: v.size)
            why = within + worst.detail if kind != "notebooks" else within
            if kind == "data" and worst.size and worst.size < LAST_DIGITS:
                why = "the last digits differ, " + why
            lines.append(f"  within tolerance: {why}")
        beyond = [v for v in mine if v.status == "beyond"]
        lines += [f"  beyond: {v.detail}" for v in beyond[:NAMED]]
        if len(beyond) > NAMED:
            lines.append(f"  beyond: {len(beyond) - NAMED} more")
    for verdict in found:
        if verdict.kind == "paper":
            lines.append("paper/splinestep.pdf: " + ("identical" if verdict.status == "identical"
                                                      else "rebuilt from the data above"))
    return lines


def machines(committed, root=ROOT):
    """A line naming the machines of HEAD's outputs and of this run's
    (data/machine.txt) where they differ, else None."""
    old = committed.get("data/machine.txt")
    path = Path(root) / "data" / "machine.txt"
    if not old or not path.exists():
        return None
    old, new = old.decode().strip().split(", "), path.read_text().strip().split(", ")
    if old == new:
        return None
    changed = [i for i in range(min(len(old), len(new))) if old[i] != new[i]] or [0]
    return (f"  committed outputs made on {', '.join(old[i] for i in changed)}; "
            f"this run on {', '.join(new[i] for i in changed)}")


def readme_tables(text):
    """The README's blocks that ``make reproduce`` writes from data/."""
    return [m.group(0) for m in
            re.finditer(r"<!-- begin (\w+) -->.*?<!-- end \1 -->", text, flags=re.DOTALL)]


def report(written, root=ROOT, out=print):
    """Compare the files in ``written`` (paths this run wrote) with git HEAD's,
    print a few lines through ``out``, and return the exit status (see the
    module's docstring)."""
    written = sorted({Path(p).resolve() for p in written})
    if not written:
        out("nothing ran: no output to compare with the committed files")
        return 0
    try:
        committed = committed_versions(written + [Path(root) / "README.md"], root)
        edited = edited_sources(root)
    except NoCheckout as reason:
        out(f"not compared with the committed files: {reason}")
        return 0
    found = verdicts(committed, root)
    out("compared with the committed files (git HEAD) by the rules of tests/reproduction.py:")
    machine = machines(committed, root)
    if machine:
        out(machine)
    for line in summary(found):
        out(line)
    readme = Path(root) / "README.md"
    if readme.exists() and committed.get("README.md") is not None:
        same = readme_tables(committed["README.md"].decode()) == readme_tables(readme.read_text())
        out("README.md tables: " + ("identical" if same else "rewritten from data/ above"))
    beyond = [v.name for v in found if v.status == "beyond"]
    if not beyond:
        out("reproduced: every output identical to the committed one or within tolerance")
        return 0
    if edited:
        shown = [name for k, name in enumerate(edited) if len(", ".join(edited[:k + 1])) < 60]
        more = f" and {len(edited) - len(shown)} more" if len(edited) > len(shown) else ""
        out(f"  sources edited since HEAD: {', '.join(shown) or edited[0]}{more}")
        out(f"changed: {len(beyond)} outputs beyond tolerance of HEAD's, made from edited sources "
            "(not a failed reproduction)")
        return 0
    out(f"NOT REPRODUCED: {len(beyond)} outputs beyond tolerance (left as written; git diff "
        "shows them)")
    return NOT_REPRODUCED
