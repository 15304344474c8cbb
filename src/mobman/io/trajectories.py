"""Configuration paths q(t) saved beside a run's results, with the identity of the robot that moved.

``trajectories.json`` holds one or more motions, each ``{"label", "robot": {"name", "parameters", "factory"},
"t", "q"}`` (q: one row per time sample, in the robot's coordinate order; ``factory``, when the robot is not a
built-in one with these parameters, names the function ``module:function`` of mobman that builds it). ``mobman simulate --out``, ``mobman plan --out``
and the reproductions with a motion write it; ``mobman view`` and :class:`mobman.viz.viewer.Viewer` read it.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Sequence

import numpy as np
import numpy.typing as npt

from mobman.errors import InputError
from mobman.io.output import write_text
from mobman.io.results import to_jsonable
from mobman.io.spec import read_text
from mobman.model.robot import MobileManipulator

FILENAME = "trajectories.json"
MAX_BYTES = 1 << 30
"""Largest trajectories file read (1 GiB)."""


@dataclass(frozen=True)
class Motion:
    """One motion: a label, the robot's name and parameters (and its builder ``factory``, "" for a built-in
    robot), sample times t (T,) and configurations q (T, n_q)."""

    label: str
    robot_name: str
    parameters: tuple[tuple[str, float], ...]
    t: np.ndarray
    q: np.ndarray
    factory: str = ""

    @classmethod
    def of(
        cls,
        label: str,
        robot: MobileManipulator,
        t: npt.ArrayLike,
        q: npt.ArrayLike,
        factory: Callable[[], MobileManipulator] | None = None,
    ) -> "Motion":
        """The motion of ``robot`` through configurations ``q`` at times ``t``; ``factory``: the function without
        arguments that builds ``robot`` when it is not a built-in robot with its parameters."""
        name = "" if factory is None else f"{factory.__module__}:{factory.__qualname__}"
        return cls(
            label, robot.name, robot.parameters, np.asarray(t, dtype=float), np.asarray(q, dtype=float), name
        )

    def describes(self, robot: MobileManipulator) -> bool:
        """Whether this motion was made by ``robot`` (same name and parameters, to 1e-12 relative)."""
        mine, theirs = dict(self.parameters), dict(robot.parameters)
        return (
            self.robot_name == robot.name
            and mine.keys() == theirs.keys()
            and all(math.isclose(mine[k], theirs[k], rel_tol=1e-12, abs_tol=1e-15) for k in mine)
        )

    @property
    def robot_label(self) -> str:
        """``name (p1=v1, p2=v2)``: the robot as a person reads it."""
        params = ", ".join(f"{k}={v:.6g}" for k, v in self.parameters)
        return f"{self.robot_name} ({params})" if params else self.robot_name


def write(folder: Path | str, motions: Sequence[Motion]) -> Path:
    """Write ``motions`` to ``folder/trajectories.json``; returns the file's path."""
    path = Path(folder) / FILENAME
    entries = [
        {
            "label": m.label,
            "robot": {"name": m.robot_name, "parameters": dict(m.parameters), "factory": m.factory},
            "t": m.t,
            "q": m.q,
        }
        for m in motions
    ]
    return write_text(path, json.dumps(to_jsonable({"motions": entries}), separators=(",", ":")))


def locate(path: Path | str) -> Path:
    """The trajectories file of a results folder, of a ``results.json`` (the file beside it), or the file itself."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"--results {path}: no such file or folder")
    candidate = path / FILENAME if path.is_dir() else path.with_name(FILENAME)
    if not candidate.is_file():
        raise InputError(
            f"--results {path}: no {FILENAME} there (written by mobman simulate --out, mobman plan --out "
            "and mobman reproduce)"
        )
    return candidate


def read(path: Path | str) -> list[Motion]:
    """The motions saved in a results folder or file (see :func:`locate`)."""
    file = locate(path)
    text = read_text(file, f"--results {file}", limit=MAX_BYTES)
    try:
        data = json.loads(text)
        motions = []
        for entry in data["motions"]:
            robot = entry["robot"]
            parameters = robot.get("parameters", {}) if isinstance(robot, dict) else None
            if not isinstance(parameters, dict):
                raise ValueError("a motion's robot must be a table with a name and a table of parameters")
            t = np.asarray(entry["t"], dtype=float)
            q = np.asarray(entry["q"], dtype=float)
            if t.ndim != 1 or q.ndim != 2 or q.shape[0] != t.shape[0] or t.size == 0:
                raise ValueError("t and q sizes differ")
            params = tuple((str(k), float(v)) for k, v in parameters.items())
            factory = str(robot.get("factory", ""))
            motions.append(Motion(str(entry["label"]), str(robot["name"]), params, t, q, factory))
    except RecursionError:
        raise InputError(f"--results {file}: not a readable trajectories file (nested too deeply)") from None
    except (ValueError, KeyError, TypeError) as exc:
        raise InputError(f"--results {file}: not a readable trajectories file ({exc})") from None
    if not motions:
        raise InputError(f"--results {file}: holds no motion")
    return motions


__all__ = ["FILENAME", "Motion", "locate", "read", "write"]
