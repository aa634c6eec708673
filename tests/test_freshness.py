"""make reproduce reruns only what changed (scripts/freshness.py): a record
of each notebook's inputs and outputs by content, so that a changed source,
module it imported or data file read makes it stale (a module it did not import does not), and so does a changed or
missing output; file times play no part."""

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import freshness  # noqa: E402


def _repository(tmp_path):
    (tmp_path / "src" / "pkg").mkdir(parents=True)
    (tmp_path / "src" / "pkg" / "a.py").write_text("x = 1\n")
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "in.csv").write_text("a\n1\n")
    (tmp_path / "data" / "out.csv").write_text("b\n2\n")
    (tmp_path / "nb.py").write_text("# notebook\n")
    state = freshness.State(tmp_path / "build" / "state.json", tmp_path)
    # A module it imported is among what it read (outputs.note_run).
    state.record("nb", [tmp_path / "nb.py"],
                 reads=[tmp_path / "data" / "in.csv", tmp_path / "src" / "pkg" / "a.py"],
                 outputs=["data/out.csv"])
    (tmp_path / "src" / "pkg" / "b.py").write_text("y = 1\n")   # a module it did not import
    return state


def test_a_notebook_is_up_to_date_until_an_input_or_output_changes(tmp_path):
    state = _repository(tmp_path)
    sources = [tmp_path / "nb.py"]
    assert state.why_stale("nb", sources) is None
    # The record is read back by a new State (another make reproduce).
    again = freshness.State(tmp_path / "build" / "state.json", tmp_path)
    assert again.why_stale("nb", sources) is None
    assert again.why_stale("other", sources) == "never run here"
    # Times alone change nothing.
    os.utime(tmp_path / "nb.py", (0, 0))
    assert again.why_stale("nb", sources) is None
    (tmp_path / "src" / "pkg" / "b.py").write_text("y = 2\n")
    assert again.why_stale("nb", sources) is None
    for path, text, why in [("src/pkg/a.py", "x = 2\n", "its inputs changed"),
                            ("data/in.csv", "a\n3\n", "its inputs changed"),
                            ("nb.py", "# edited\n", "its inputs changed"),
                            ("data/out.csv", "b\n5\n", "data/out.csv changed")]:
        old = (tmp_path / path).read_text()
        (tmp_path / path).write_text(text)
        assert again.why_stale("nb", sources) == why, path
        (tmp_path / path).write_text(old)
        assert again.why_stale("nb", sources) is None
    (tmp_path / "data" / "out.csv").unlink()
    assert again.why_stale("nb", sources) == "data/out.csv is missing"


def test_a_forgotten_notebook_runs_again(tmp_path):
    state = _repository(tmp_path)
    state.forget("nb")
    again = freshness.State(tmp_path / "build" / "state.json", tmp_path)
    assert again.why_stale("nb", [tmp_path / "nb.py"]) == "never run here"


def test_the_manifest_of_a_run(tmp_path):
    manifest = tmp_path / "m.txt"
    manifest.write_text("read /r/data/a.csv\nwrote /r/figures/b.png\nwrote /r/data/c.csv\n")
    assert freshness.read_manifest(manifest) == (
        ["/r/data/a.csv"], ["/r/figures/b.png", "/r/data/c.csv"])
    assert freshness.read_manifest(tmp_path / "none.txt") == ([], [])


def test_the_claims_notebook_runs_whenever_another_does(tmp_path, monkeypatch):
    """reproduce.to_run: a stale notebook makes the claims notebook run
    too, whatever the order of the list it is found in (here the claims
    notebook is listed before the stale one)."""
    import reproduce
    notebooks = [tmp_path / f"{name}.py" for name in ("01_a", "14_claims_and_errata", "08_b")]
    for path in notebooks:
        path.write_text(f"# {path.stem}\n")
    monkeypatch.setattr(reproduce, "NOTEBOOKS", notebooks)
    monkeypatch.setattr(reproduce, "ROOT", tmp_path)
    state = freshness.State(tmp_path / "state.json", tmp_path)
    for path in notebooks:
        state.record(path.stem, [path])
    assert reproduce.to_run(state) == []
    notebooks[2].write_text("# 08_b, edited\n")
    assert [(s.stem, why) for s, why in reproduce.to_run(state)] == [
        ("14_claims_and_errata", "the others' data may have changed"),
        ("08_b", "its inputs changed")]


def test_a_folder_output_is_stale_when_any_file_in_it_changes(tmp_path):
    """The site is recorded as its whole folder: a deleted page makes it stale."""
    (tmp_path / "site" / "a").mkdir(parents=True)
    (tmp_path / "site" / "index.html").write_text("x")
    (tmp_path / "site" / "a" / "page.html").write_text("y")
    (tmp_path / "in.txt").write_text("z")
    state = freshness.State(tmp_path / "state.json", tmp_path)
    state.record("site", [tmp_path / "in.txt"], outputs=["site"], common=False)
    assert state.why_stale("site", [tmp_path / "in.txt"], common=False) is None
    (tmp_path / "site" / "a" / "page.html").unlink()
    assert state.why_stale("site", [tmp_path / "in.txt"], common=False) == "site changed"


def test_inputs_are_taken_before_the_run(tmp_path):
    """A source edited while its notebook runs leaves the notebook stale."""
    source = tmp_path / "nb.py"
    source.write_text("# first\n")
    state = freshness.State(tmp_path / "state.json", tmp_path)
    before = state.before([source])
    source.write_text("# edited during the run\n")
    state.record("nb", [source], before=before)
    assert state.why_stale("nb", [source]) == "its inputs changed"


def test_naming_a_notebook_runs_the_claims_notebook_too(monkeypatch, tmp_path):
    import reproduce
    notebooks = [tmp_path / f"{name}.py" for name in ("01_a", "14_claims_and_errata", "08_b")]
    monkeypatch.setattr(reproduce, "NOTEBOOKS", notebooks)
    state = freshness.State(tmp_path / "state.json", tmp_path)
    assert [(s.stem, why) for s, why in reproduce.to_run(state, ["08"])] == [
        ("08_b", "asked for"), ("14_claims_and_errata", "the others' data may have changed")]
    assert [s.stem for s, _ in reproduce.to_run(state, ["14"])] == ["14_claims_and_errata"]


def test_the_paper_is_rebuilt_from_every_file_it_reads():
    """Every file paper/splinestep.typ reads (csv(), read(), yaml(), image())
    is among the paper's hashed sources."""
    import re
    import reproduce
    text = (ROOT / "paper" / "splinestep.typ").read_text()
    read = set(re.findall(r'(?:csv|read|yaml|json)\("/([^"]+)"', text))
    sources = {str(p.relative_to(ROOT)) for p in reproduce._paper_sources()}
    assert read and read <= sources, read - sources
    figures = {f"figures/{p.name}" for p in (ROOT / "figures").glob("*.pdf")}
    assert figures <= sources


def test_outputs_notes_what_a_notebook_reads_and_writes(tmp_path):
    """scripts/outputs.py, with SPLINESTEP_MANIFEST set, notes each data file
    read and each data file and figure written."""
    import subprocess
    manifest = tmp_path / "manifest.txt"
    code = ("import sys; sys.path.insert(0, %r); import outputs, pandas as pd; "
            "plt = outputs.setup(); outputs.save_data(pd.DataFrame({'a': [1]}), 'x'); "
            "outputs.read_data('x'); fig = plt.figure(figsize=(outputs.WIDTH, 2)); "
            "outputs.save_figure(fig, 'f')") % str(ROOT / "scripts")
    env = dict(os.environ, SPLINESTEP_MANIFEST=str(manifest), SPLINESTEP_OUTPUT=str(tmp_path),
               MPLBACKEND="Agg")
    subprocess.run([sys.executable, "-c", code], check=True, env=env)
    reads, writes = freshness.read_manifest(manifest)
    assert reads == [str(tmp_path / "data" / "x.csv")]
    assert writes == [str(tmp_path / "data" / "x.csv"), str(tmp_path / "figures" / "f.pdf"),
                      str(tmp_path / "figures" / "f.png")]


def test_a_run_under_other_cpu_kernels_is_another_run(monkeypatch, tmp_path):
    """make test-emulated (numpy's newer kernels off) does not count as the
    run make reproduce made natively: its notebooks run again."""
    for name in list(os.environ):   # recorded natively, whatever this session runs under
        if name.startswith(freshness.ENVIRONMENT_PREFIXES):
            monkeypatch.delenv(name)
    state = _repository(tmp_path)
    sources = [tmp_path / "nb.py"]
    assert freshness.reproduced([tmp_path / "nb.py"], state) == {"nb": ["data/out.csv"]}
    monkeypatch.setenv("NPY_DISABLE_CPU_FEATURES", "AVX512_ICL X86_V4 X86_V3")
    assert state.why_stale("nb", sources) == "its inputs changed"
    assert freshness.reproduced([tmp_path / "nb.py"], state) == {}
    monkeypatch.delenv("NPY_DISABLE_CPU_FEATURES")
    assert state.why_stale("nb", sources) is None
    for name, value in [("NPY_ENABLE_CPU_FEATURES", "SSE,SSE2"), ("OPENBLAS_CORETYPE", "Haswell"),
                        ("NUMBA_DISABLE_JIT", "1")]:
        monkeypatch.setenv(name, value)
        assert state.why_stale("nb", sources) == "its inputs changed", name
        monkeypatch.delenv(name)


def test_a_run_notes_the_modules_it_imported_and_its_costs(tmp_path):
    """outputs.note_run, which make reproduce runs after a notebook's last
    cell: the repository's modules the run imported, none it did not, and
    its CPU and compile seconds (the compile seconds at most the CPU's)."""
    import subprocess
    manifest = tmp_path / "manifest.txt"
    code = ("import sys; sys.path.insert(0, %r); import outputs, numpy as np, splinestep; "
            "splinestep.solve(lambda t, y, yp: -y, (0, 1), np.ones(1), np.zeros(1), h=0.1); "
            "outputs.note_run()") % str(ROOT / "scripts")
    env = dict(os.environ, SPLINESTEP_MANIFEST=str(manifest), SPLINESTEP_OUTPUT=str(tmp_path))
    subprocess.run([sys.executable, "-c", code], check=True, env=env)
    reads, writes = freshness.read_manifest(manifest)
    names = {Path(r).relative_to(ROOT).as_posix() for r in reads}
    assert {"scripts/outputs.py", "src/splinestep/driver.py", "src/splinestep/step.py"} <= names
    assert "src/splinestep/analysis/theory.py" not in names and writes == []
    costs = freshness.run_costs(manifest)
    assert 0 <= costs["compile"] <= costs["cpu"]


def test_a_module_edited_while_a_notebook_runs_leaves_it_stale(tmp_path):
    """The modules are hashed before the run (State.snapshot): one edited
    while the notebook runs is not recorded as what the run used."""
    state = _repository(tmp_path)
    snapshot = state.snapshot()
    assert "src/pkg/a.py" in snapshot
    (tmp_path / "src" / "pkg" / "a.py").write_text("x = 3\n")   # edited during the run
    assert not state.record("nb", [tmp_path / "nb.py"], reads=[tmp_path / "src" / "pkg" / "a.py"],
                            outputs=["data/out.csv"], snapshot=snapshot)
    assert state.why_stale("nb", [tmp_path / "nb.py"]) == "never run here"
    assert state.record("nb", [tmp_path / "nb.py"], reads=[tmp_path / "src" / "pkg" / "a.py"],
                        outputs=["data/out.csv"], snapshot=state.snapshot())
    assert state.why_stale("nb", [tmp_path / "nb.py"]) is None
