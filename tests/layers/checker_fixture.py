"""What the checker tests share: the repository they run on, a script of scripts/ loaded as a
module (the checkers have no .py suffix), and a throw-away git repository with planted files."""
import importlib.machinery
import importlib.util
import os
import subprocess
import sys
import tempfile

REPO = os.path.abspath(sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", ".."))


def load_script(name):
    """(path, module) of scripts/NAME."""
    path = os.path.join(REPO, "scripts", name)
    loader = importlib.machinery.SourceFileLoader(name.replace("-", "_"), path)
    module = importlib.util.module_from_spec(importlib.util.spec_from_loader(loader.name, loader))
    loader.exec_module(module)
    return path, module


def fake_repo(files):
    """A temporary git repository holding `files` ({path: text}), all tracked."""
    d = tempfile.mkdtemp()
    for path, text in files.items():
        os.makedirs(os.path.join(d, os.path.dirname(path)), exist_ok=True)
        with open(os.path.join(d, path), "w") as f:
            f.write(text)
    subprocess.run(["git", "init", "-q", d], check=True)
    subprocess.run(["git", "-C", d, "add", "-A"], check=True)
    return d
