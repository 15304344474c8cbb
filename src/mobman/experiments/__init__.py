"""One module per paper reproduction; each rebuilds its examples, figures, ``results.json`` and a report.

Every module exposes ``TITLE`` and ``run(out: Path, quick: bool = False) -> Reproduction``. ``quick`` selects
the reduced resolution used by the test suite; the default resolution is the one ``mobman reproduce all``
uses (the whole set stays within a few minutes on two cores).
"""

from __future__ import annotations

import importlib
from types import ModuleType

REPRODUCTIONS: dict[str, str] = {
    "bayle2003": "mobman.experiments.bayle2003",
    "nait-chabane2006": "mobman.experiments.nait_chabane2006",
    "korayem-kinematics": "mobman.experiments.korayem_kinematics",
    "tchon2002": "mobman.experiments.tchon2002",
    "yamamoto1999": "mobman.experiments.yamamoto1999",
    "korayem-load": "mobman.experiments.korayem_load",
}


def module(name: str) -> ModuleType:
    """The module of a reproduction by its command-line name."""
    return importlib.import_module(REPRODUCTIONS[name])
