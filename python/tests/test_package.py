"""The package as Python sees it: version, help, type stubs, the README's examples."""

from __future__ import annotations

import importlib.metadata
import pydoc
import re
from pathlib import Path

import vizretarget
from conftest import REPO


def test_version_is_the_packages() -> None:
    assert vizretarget.__version__ == importlib.metadata.version("vizretarget")
    cargo = (REPO / "Cargo.toml").read_text()
    assert f'version = "{vizretarget.__version__}"' in cargo  # the library's own version


def test_help_shows_the_docstrings() -> None:
    text = pydoc.render_doc(vizretarget, renderer=pydoc.plaintext)
    for needle in ["Resize a visualization to ``size``", "Retargets a stream of frames", "retarget_file", "Every method on ``image``"]:
        assert needle in text, needle


def test_stubs_ship_with_the_package() -> None:
    here = Path(vizretarget.__file__).parent
    stub = (here / "__init__.pyi").read_text()
    assert (here / "py.typed").exists()
    for name in vizretarget.__all__:
        assert re.search(rf"^(def|class) {name}\b|^{name}:", stub, re.M), name


def test_readme_python_examples_run(tmp_path, monkeypatch) -> None:
    """The README's Python examples, as written there, from the repository root."""
    readme = (REPO / "README.md").read_text()
    section = readme.split("### Python", 1)[1].split("\n### ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) >= 2
    monkeypatch.chdir(REPO)
    for code in blocks:
        code = code.replace("phone.png", str(tmp_path / "phone.png"))
        exec(compile(code, "README.md", "exec"), {})
    assert (tmp_path / "phone.png").exists()
