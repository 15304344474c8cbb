"""What a paper reproduction returns (mobman.experiments.report.Reproduction) and how write() puts it on disk:
results.json parses back to the results (arrays as lists, non-finite numbers as null), report.md starts
with the paper's title and links the figures; both files are replaced whole, never left half-written."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from mobman.experiments.report import Reproduction

TITLE = "Yamamoto & Yun (1999): coordinating locomotion and manipulation"


def _reproduction(results, figures=()) -> Reproduction:
    return Reproduction(
        "yamamoto1999", TITLE, results, "- claim 1: reproduced\n- claim 2: not reproduced", list(figures)
    )


def test_figures_default_to_an_empty_list_per_instance():
    a, b = Reproduction("a", "A", {}, ""), Reproduction("b", "B", {}, "")
    assert a.figures == [] and a.figures is not b.figures


def test_write_puts_the_results_in_results_json(tmp_path):
    results = {
        "max_load_kg": 2.5,
        "converged": True,
        "runs": [{"start": "P", "iterations": 12}, {"start": "Q", "iterations": 40}],
        "limiting_actuator": None,
    }
    _reproduction(results).write(tmp_path)
    assert json.loads((tmp_path / "results.json").read_text(encoding="utf-8")) == results


def test_results_json_holds_arrays_as_lists_and_non_finite_numbers_as_null(tmp_path):
    results = {
        "q": np.array([[0.0, 1.5], [2.0, -3.0]]),
        "pair": (1, 2),
        "unbounded": math.inf,
        "nan": math.nan,
    }
    _reproduction(results).write(tmp_path)
    text = (tmp_path / "results.json").read_text(encoding="utf-8")
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text) == {
        "q": [[0.0, 1.5], [2.0, -3.0]],
        "pair": [1, 2],
        "unbounded": None,
        "nan": None,
    }


def test_report_md_starts_with_the_title_and_links_the_figures(tmp_path):
    figures = [tmp_path / "paths_P.png", tmp_path / "convergence.png"]
    _reproduction({}, figures).write(tmp_path)
    text = (tmp_path / "report.md").read_text(encoding="utf-8")
    lines = text.splitlines()
    assert lines[0] == f"# {TITLE}"
    assert "- claim 1: reproduced\n- claim 2: not reproduced" in text
    assert lines[-2:] == ["![paths_P](paths_P.png)", "![convergence](convergence.png)"]
    assert text.endswith("\n")


def test_figures_in_a_subfolder_are_linked_by_their_path_from_the_report(tmp_path):
    _reproduction({}, [tmp_path / "figures" / "paths.png"]).write(tmp_path)
    assert (tmp_path / "report.md").read_text().rstrip().endswith("![paths](figures/paths.png)")


def test_report_without_figures_has_no_image_links(tmp_path):
    _reproduction({}).write(tmp_path)
    text = (tmp_path / "report.md").read_text(encoding="utf-8")
    assert text.splitlines()[0] == f"# {TITLE}" and "![" not in text


def test_write_creates_the_folder_and_writes_only_the_two_files(tmp_path):
    out = tmp_path / "results" / "yamamoto1999"
    _reproduction({"ok": 1}).write(out)
    assert sorted(p.name for p in out.iterdir()) == ["report.md", "results.json"]


def test_write_replaces_earlier_files_whole(tmp_path):
    _reproduction({"iterations": list(range(1000))}).write(tmp_path)
    _reproduction({"iterations": [1]}).write(tmp_path)
    assert json.loads((tmp_path / "results.json").read_text(encoding="utf-8")) == {"iterations": [1]}
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report.md", "results.json"]


def test_results_that_cannot_be_written_leave_the_earlier_files(tmp_path):
    _reproduction({"run": 1}).write(tmp_path)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    with pytest.raises(TypeError):
        _reproduction({"run": object()}).write(tmp_path)
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before  # no partial file either
