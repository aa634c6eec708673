"""`make lab` pairs the notebooks: the server it starts (scripts/lab.py),
on a copy of the repository's notebooks, opens a .py as a notebook with the
outputs of its .ipynb; a save without edits leaves both files as they
were, and an edit saved through either file reaches both."""

import json
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "scripts"))
import lab  # noqa: E402

NOTEBOOK = "notebooks/14_claims_and_errata"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(url, method="GET", body=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=30) as response:
        return json.loads(response.read() or b"null")


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    root = tmp_path_factory.mktemp("repository")
    shutil.copytree(ROOT / "notebooks", root / "notebooks")
    shutil.copy(ROOT / "jupytext.toml", root / "jupytext.toml")
    port = free_port()
    process = subprocess.Popen(
        [sys.executable, str(ROOT / "scripts" / "lab.py"), "--root", str(root), "--no-browser",
         "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}", "--ServerApp.port_retries=0",
         "--IdentityProvider.token=", "--ServerApp.password=",
         "--ServerApp.disable_check_xsrf=True", "--ServerApp.allow_root=True"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}"
    try:
        for _ in range(300):
            try:
                request(f"{url}/api/status")
                break
            except OSError:
                if process.poll() is not None:
                    pytest.fail("the lab server exited")
                time.sleep(0.2)
        else:
            pytest.fail("the lab server did not start in 60 s")
        yield url, root
    finally:
        process.terminate()
        process.wait(timeout=30)


def files(root):
    return {suffix: (root / f"{NOTEBOOK}{suffix}").read_bytes() for suffix in (".py", ".ipynb")}


def test_settings_open_python_files_as_notebooks():
    target = lab.install_settings()
    viewers = json.loads(target.read_text())["@jupyterlab/docmanager-extension:plugin"]
    assert viewers["defaultViewers"]["python"] == "Jupytext Notebook"


def test_py_opens_with_outputs_and_an_unedited_save_changes_nothing(server):
    url, root = server
    before = files(root)
    model = request(f"{url}/api/contents/{NOTEBOOK}.py?type=notebook&content=1")
    code = [c for c in model["content"]["cells"] if c["cell_type"] == "code"]
    stored = [c for c in json.loads(before[".ipynb"])["cells"] if c["cell_type"] == "code"]
    assert any(c["outputs"] for c in code), "the .py opened without outputs"
    assert [len(c["outputs"]) for c in code] == [len(c["outputs"]) for c in stored]
    request(f"{url}/api/contents/{NOTEBOOK}.py", "PUT",
            {"type": "notebook", "format": "json", "content": model["content"]})
    assert files(root) == before


def test_an_edit_reaches_both_files(server):
    url, root = server
    model = request(f"{url}/api/contents/{NOTEBOOK}.ipynb?type=notebook&content=1")
    markdown = next(c for c in model["content"]["cells"] if c["cell_type"] == "markdown")
    markdown["source"] = "".join(markdown["source"]) + "\nAn edit made in the lab."
    request(f"{url}/api/contents/{NOTEBOOK}.ipynb", "PUT",
            {"type": "notebook", "format": "json", "content": model["content"]})
    after = files(root)
    assert b"An edit made in the lab." in after[".py"]
    assert b"An edit made in the lab." in after[".ipynb"]
