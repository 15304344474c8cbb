"""coal (hpp-fcl) as the reference of the distance tests: shapes and one signed distance query."""

from __future__ import annotations

import coal
import numpy as np


def coal_shape(shape: str, size: tuple[float, ...]) -> coal.ShapeBase:
    """The coal shape of an obstacle's shape and size (a capsule's length: its straight part, as mobman's)."""
    if shape == "box":
        return coal.Box(*size)
    if shape == "sphere":
        return coal.Sphere(size[0])
    if shape == "cylinder":
        return coal.Cylinder(size[0], size[1])
    return coal.Capsule(size[0], size[1])


def coal_distance(a: coal.ShapeBase, ta: coal.Transform3s, b: coal.ShapeBase, tb: coal.Transform3s) -> tuple:
    """(signed distance, nearest point on a, nearest point on b, normal from a to b) by coal, with tight GJK and
    EPA tolerances."""
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    request.gjk_tolerance = 1e-12
    request.epa_tolerance = 1e-12
    d = coal.distance(a, ta, b, tb, request, result)
    return (
        d,
        np.array(result.getNearestPoint1()),
        np.array(result.getNearestPoint2()),
        np.array(result.normal),
    )
