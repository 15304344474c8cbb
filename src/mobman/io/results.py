"""JSON output of results holding NumPy/JAX arrays."""

from __future__ import annotations

import json
import math
from typing import Any


def to_jsonable(obj: Any) -> Any:
    """Arrays → nested lists, tuples → lists, non-finite floats → None (JSON has no NaN)."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if hasattr(obj, "tolist"):
        return to_jsonable(obj.tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dump_json(obj: Any) -> str:
    """Indented JSON text of ``obj`` (see :func:`to_jsonable`)."""
    return json.dumps(to_jsonable(obj), indent=2)
