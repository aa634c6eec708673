"""Which outputs are up to date: content hashes, as make or snakemake decide
staleness, but on contents, not file times (a fresh clone's times say
nothing).

A notebook is up to date when its inputs and its outputs hash as they did
when ``make reproduce`` last ran it here.  Its inputs are its own source,
the scripts it runs with (:data:`COMMON`), the environment
(``environment.txt``, the Python version, the CPU, the installed packages
and the variables that choose CPU kernels, :func:`environment`), every data file it read and
every module of the repository's ``src/`` and ``scripts/`` it imported (the
package's modules it used, an analysis module only if it imported it; a
module edited while it ran leaves it stale); its outputs are its ``.ipynb`` and
every data file and figure it wrote.  What a notebook read and wrote is
recorded as it runs (``scripts/outputs.py`` appends to the file named by
``SPLINESTEP_MANIFEST``).  The record lives in ``build/reproduce-state.json``,
which is not committed: a fresh clone runs everything.
"""

import functools
import hashlib
import json
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STATE = ROOT / "build" / "reproduce-state.json"
# Inputs of every notebook besides its own source and what it reads.
# The modules a notebook imports (the package's, the scripts') are among what
# it read (outputs.note_run): an edit of one reruns the notebooks that import it.
COMMON = ("pyproject.toml", "environment.txt", "scripts/outputs.py", "scripts/reproduce.py")


def files(patterns, root=ROOT):
    """The files matching ``patterns`` (globs relative to ``root``), sorted."""
    found = set()
    for pattern in patterns:
        found.update(p for p in Path(root).glob(pattern) if p.is_file())
    return sorted(found)


def file_hash(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def digest(paths, root=ROOT, extra=""):
    """One hash of the names (relative to ``root``) and contents of ``paths``
    and the text ``extra``; a missing file counts as its name alone."""
    total = hashlib.sha256(extra.encode())
    for path in sorted(Path(p) for p in paths):
        total.update(str(path.relative_to(root)).encode() + b"\0")
        total.update(path.read_bytes() if path.exists() else b"(missing)")
    return total.hexdigest()


def output_hash(path):
    """The hash of a file, or of a folder's files (names and contents)."""
    path = Path(path)
    if path.is_dir():
        return digest([p for p in path.rglob("*") if p.is_file()], path)
    return file_hash(path)


# Variables that change what a run computes on this machine: numpy's,
# numba's and the BLAS libraries' choices of CPU kernels and threads
# (make test-emulated sets some of them), by their prefixes.
ENVIRONMENT_PREFIXES = ("NPY_", "NUMBA_", "OPENBLAS_", "MKL_", "OMP_")


def _cpu():
    """The CPU's model name (Linux), or the platform's processor string."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.partition(":")[2].strip()
    except OSError:
        pass
    import platform
    return platform.processor() or platform.machine()


def environment():
    """What a run computes with besides the files it reads: the Python
    version, the CPU, the installed distributions and their versions, and
    the variables of :data:`ENVIRONMENT_PREFIXES` that are set; a run under
    other ones is another run."""
    variables = sorted(f"{k}={v}" for k, v in os.environ.items()
                       if k.startswith(ENVIRONMENT_PREFIXES))
    return "\n".join([f"Python {sys.version}", f"CPU {_cpu()}", *_packages(), *variables])


@functools.cache
def _packages():
    """The installed distributions, name==version, sorted (once per process)."""
    from importlib import metadata
    return tuple(sorted(f"{d.metadata['Name']}=={d.version}" for d in metadata.distributions()))


# The modules a run may import, hashed before it starts (State.snapshot):
# one edited while the run goes on leaves it stale.
MODULES = ("src/**/*.py", "scripts/*.py")


def reproduced(notebooks, state=None):
    """The notebooks (percent scripts) that ``make reproduce`` ran here with
    the inputs they have now and whose outputs are as that run wrote them:
    {stem: [the output files, relative to the root]}."""
    state = State() if state is None else state
    return {script.stem: sorted(state.records[script.stem]["outputs"])
            for script in notebooks if state.why_stale(script.stem, [script]) is None}


class State:
    """The record of what ran: ``{name: {"inputs": hash, "reads": [paths],
    "outputs": {path: hash}}}`` in ``build/reproduce-state.json``."""

    def __init__(self, path=STATE, root=ROOT):
        self.path, self.root = Path(path), Path(root)
        try:
            self.records = json.loads(self.path.read_text())
        except (OSError, ValueError):
            self.records = {}

    def before(self, sources, common=True):
        """The hash of what a run takes besides the files it reads: its
        ``sources``, with ``common`` the files of :data:`COMMON` and the
        environment.  Taken before the run, so that one of these files
        edited while it runs leaves it stale (the modules it imports are
        guarded by :meth:`snapshot`; a data file it reads is hashed when the
        run is recorded)."""
        paths = (files(COMMON, self.root) if common else []) + [Path(s) for s in sources]
        return digest(paths, self.root, environment())

    def _inputs(self, sources, reads, common=True, before=None):
        own = self.before(sources, common) if before is None else before
        return digest([self.root / r for r in reads], self.root, own)

    def why_stale(self, name, sources, common=True):
        """None if ``name`` is up to date, else why not (a short phrase).
        ``sources`` are its own input files (absolute paths); with
        ``common``, the files of :data:`COMMON` and the environment too."""
        record = self.records.get(name)
        if record is None:
            return "never run here"
        if self._inputs(sources, record["reads"], common) != record["inputs"]:
            return "its inputs changed"
        for path, expected in record["outputs"].items():
            target = self.root / path
            if not target.exists():
                return f"{path} is missing"
            if output_hash(target) != expected:
                return f"{path} changed"
        return None

    def snapshot(self):
        """{path: hash} of the modules a run may import (:data:`MODULES`),
        taken before it starts, for :meth:`record`."""
        return {str(p.relative_to(self.root)): file_hash(p) for p in files(MODULES, self.root)}

    def record(self, name, sources, reads=(), outputs=(), common=True, before=None,
               snapshot=None):
        """Note that ``name`` ran, with these inputs and outputs (files or
        folders; paths relative to the root or absolute below it), and save
        the record.  ``before`` is :meth:`before` as taken when the run
        started (taken now if None), ``snapshot`` :meth:`snapshot`: a module
        it read that changed since then (edited while it ran) leaves it
        stale, unrecorded.  Returns whether it was recorded."""
        relative = [str(Path(p).resolve().relative_to(self.root)) if Path(p).is_absolute()
                    else str(p) for p in reads]
        relative = sorted(set(relative))
        if snapshot is not None and any(
                r in snapshot and file_hash(self.root / r) != snapshot[r] for r in relative):
            self.forget(name)
            return False
        written = {}
        for path in outputs:
            path = Path(path) if Path(path).is_absolute() else self.root / path
            written[str(path.relative_to(self.root))] = output_hash(path)
        self.records[name] = {"inputs": self._inputs(sources, relative, common, before),
                              "reads": relative,
                              "outputs": written}
        self.save()
        return True

    def forget(self, name):
        self.records.pop(name, None)
        self.save()

    def save(self):
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.path.write_text(json.dumps(self.records, indent=1, sort_keys=True) + "\n")


def _manifest_lines(path):
    try:
        return [line.partition(" ") for line in Path(path).read_text().splitlines()]
    except OSError:
        return []


def read_manifest(path):
    """(paths read, paths written) from a manifest ``scripts/outputs.py``
    wrote: the data files and, at the end of a run, the modules imported
    (read); the data files and figures written."""
    reads, writes = [], []
    for kind, _, name in _manifest_lines(path):
        if kind == "read":
            reads.append(name)
        elif kind == "wrote":
            writes.append(name)
    return reads, writes


def run_costs(path):
    """{"compile": s, "cpu": s} from a manifest (:func:`outputs.note_run`):
    the seconds numba compiled and the CPU seconds of the notebook's
    kernel; empty if the run did not note them."""
    return {kind: float(value) for kind, _, value in _manifest_lines(path)
            if kind in ("compile", "cpu")}
