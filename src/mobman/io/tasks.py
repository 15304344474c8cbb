"""Tasks from the tables of specification and robot files: ``[task]``, ``tasks = [{kind = …}, …]``.

A table names a registered task kind (:func:`mobman.model.tasks.task_kinds`) and gives the task's fields;
the rest is generic (:func:`mobman.io.spec.dataclass_values`): the allowed keys are the dataclass fields, each
value converted by its annotation, the defaults those of the dataclass; nested task tables (a stack's
``tasks``) are read by :func:`task` again, and the kind's ``from_table`` hook builds the task.

```toml
[task]
kind = "stack"
tasks = [{ kind = "position", components = "xy" }, { kind = "planar_angle", sequence = "ZXY" }]
```
"""

from __future__ import annotations

from typing import Any

from mobman.errors import InputError
from mobman.io import spec as fields
from mobman.model.tasks import Task, task_class, task_kinds


def task(entries: Any, field: str) -> Task:
    """The task described by the table ``entries`` (at ``field``, e.g. ``"task"``); every mistake raises
    :class:`~mobman.InputError` naming the field and what is allowed."""
    if not isinstance(entries, dict):
        raise InputError(f"{field}: must be a task table ({{kind = ...}}), got {entries!r:.60}")
    cls = fields.kind(entries, field, {kind: task_class(kind) for kind in task_kinds()})
    values = fields.dataclass_values(cls, entries, field, choices=cls.choices, convert={Task: task})
    return fields.build(field, lambda: cls.from_table(values))


__all__ = ["task"]
