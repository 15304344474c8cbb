"""``mobman simulate --scene FILE`` (or a spec's ``[scene]``): the scene given to the QP law, and what is said up
front: a start in collision (which pair, how deep; the law then pushes the pair apart) and a target inside an
obstacle, each a warning line and an entry of the run's metrics."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import typer

from mobman.errors import InputError
from mobman.model.tasks import Pose, Position

if TYPE_CHECKING:
    from mobman.control.spec import Spec


def prepare(parsed: Spec, scene_path: Path | None) -> tuple[Spec, dict]:
    """The spec with the ``--scene`` file's obstacles given to its law (a spec's own ``[scene]`` then gives
    way: refused), and the warnings' metrics: ``start_collision`` and ``target_obstacle`` (None when all is
    clear; absent without a scene)."""
    from mobman.control import avoidance, spec
    from mobman.control.laws import WholeBodyQP
    from mobman.io import scene as scene_file

    law = parsed.law
    if scene_path is not None:
        if getattr(law, "scene", None) is not None:
            raise InputError("--scene: the spec has a scene already; give one of [scene] and --scene")
        parsed = dataclasses.replace(parsed, law=spec.with_scene(law, scene_file.load(scene_path)))
        law = parsed.law
    if not isinstance(law, WholeBodyQP) or law.scene is None:
        return parsed, {}
    scene = law.scene
    start = avoidance.start_collision(
        law.collision_model(parsed.robot), scene, parsed.q0, law.collision_margin
    )
    if start is not None:
        typer.echo(
            f"warning: q0 is in collision: {start['pair'][0]} against {start['pair'][1]} at "
            f"{start['distance']:.3f} m, {start['depth']:.3f} m inside the margin; the law pushes them apart",
            err=True,
        )
    task = law.controlled_task(parsed.task)
    inside = None
    if (isinstance(task, Position) and task.components == "xyz") or isinstance(task, Pose):
        end = parsed.reference(np.array(parsed.duration))[0]
        inside = avoidance.target_inside(scene, np.asarray(end)[:3])
        if inside is not None:
            typer.echo(
                f"warning: the target lies inside obstacle {inside['obstacle']!r}, {inside['depth']:.3f} m "
                "deep: the law keeps out of it and cannot reach it",
                err=True,
            )
    return parsed, {"start_collision": start, "target_obstacle": inside}


__all__ = ["prepare"]
