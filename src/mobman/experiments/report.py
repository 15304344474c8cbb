"""What a reproduction returns, and how it is written to disk."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from mobman.io import dump_json
from mobman.io.output import write_text


@dataclass
class Reproduction:
    """The outcome of one paper reproduction.

    name: command-line name; title: the paper; results: what goes to ``results.json``; report: markdown
    (claims checked, settings chosen, what could not be reproduced); figures: PNG files written.
    """

    name: str
    title: str
    results: Any
    report: str
    figures: list[Path] = field(default_factory=list)

    def write(self, out: Path) -> None:
        """Write ``results.json`` and ``report.md`` into ``out`` (figures are written by the experiment; the report
        links them relative to ``out``)."""
        write_text(out / "results.json", dump_json(self.results))
        figures = "\n".join(f"![{p.stem}]({Path(os.path.relpath(p, out)).as_posix()})" for p in self.figures)
        write_text(out / "report.md", f"# {self.title}\n\n{self.report}\n\n{figures}\n")
