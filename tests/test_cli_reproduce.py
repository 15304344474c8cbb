"""`mobman reproduce` (mobman.cli.reproduce): the registry of reproductions, each result written with an index."""

import json
from types import SimpleNamespace

from mobman.cli import main
from mobman.experiments import REPRODUCTIONS
from mobman.experiments.report import Reproduction


def test_every_registered_reproduction_module_exists():
    from mobman.experiments import module

    for name in REPRODUCTIONS:
        mod = module(name)
        assert callable(mod.run) and isinstance(mod.TITLE, str), name


def test_reproduce_all_writes_each_result_and_an_index(tmp_path, monkeypatch, capsys):
    ran = []

    def fake(name):
        def run(out, quick=False):
            ran.append((name, quick))
            return Reproduction(name, f"title of {name}", {"name": name}, "report text")

        return SimpleNamespace(run=run)

    monkeypatch.setattr("mobman.cli.reproduce.module", fake)
    main(["reproduce", "all", "--out", str(tmp_path), "--quick"])
    assert ran == [(name, True) for name in REPRODUCTIONS]
    for name in REPRODUCTIONS:
        assert json.loads((tmp_path / name / "results.json").read_text()) == {"name": name}
        assert (tmp_path / name / "report.md").read_text().startswith(f"# title of {name}")
    index = (tmp_path / "index.md").read_text()
    assert all(f"[{name}]({name}/report.md)" in index for name in REPRODUCTIONS)
