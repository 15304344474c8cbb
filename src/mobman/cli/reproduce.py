"""``mobman reproduce NAME|all``: rebuild the papers' examples, figures and reports."""

from __future__ import annotations

import time
from pathlib import Path

import typer
from rich.console import Console

from mobman.cli.app import app
from mobman.errors import InputError
from mobman.experiments import REPRODUCTIONS, module
from mobman.io.output import check_folder, parent_folder, results_folder, write_text


@app.command("reproduce")
def reproduce_command(
    name: str = typer.Argument(..., help=f"one of: all, {', '.join(REPRODUCTIONS)}"),
    out: Path = typer.Option(
        Path("mobman-results"), "--out", help="Output folder (one subfolder per paper)."
    ),
    quick: bool = typer.Option(False, "--quick", help="Reduced resolution (as in the test suite)."),
) -> None:
    """Reproduce one paper's worked examples (or all of them) into OUT, with an index page."""
    names = list(REPRODUCTIONS) if name == "all" else [name]
    for n in names:
        if n not in REPRODUCTIONS:
            raise InputError(f"unknown reproduction {n!r}; choose among: all, {', '.join(REPRODUCTIONS)}")
    check_folder(out, "reproduce")
    for n in names:
        check_folder(out / n, "reproduce")
    parent_folder(out, "reproduce")
    console = Console(stderr=True)
    rows = []
    for n in names:
        start = time.perf_counter()
        with console.status(f"reproducing {n} …"), results_folder(out / n, "reproduce") as staging:
            result = module(n).run(staging, quick=quick)
            result.write(staging)
        elapsed = time.perf_counter() - start
        console.print(f"[green]✓[/green] {n}: {result.title} ({elapsed:.1f} s) → {out / n}")
        rows.append((n, result.title, elapsed))
    if name == "all":
        lines = ["# mobman reproductions", "", "| reproduction | paper | time (s) |", "|---|---|---|"]
        lines += [f"| [{n}]({n}/report.md) | {title} | {t:.1f} |" for n, title, t in rows]
        write_text(out / "index.md", "\n".join(lines) + "\n")
        console.print(f"index: {out / 'index.md'}")
