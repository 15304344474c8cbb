"""The URDF form of a platform: what it reads from a URDF file and the joints it writes into one.

A platform reads itself with :meth:`~mobman.model.platforms.base.Platform.from_urdf` from a
:class:`UrdfReader`, the view of the file that :mod:`mobman.io.urdf` gives it: the wheel joints off the arm
chains with their centres in the base link, grouped into axles, the steering joints, a wheel's radius, the
joints' speed limits, the base link's height above the ground the wheels stand on, and the values the caller
passed (``wheels=``, ``wheel_radius=``, ``half_track=``, ``platform_options=``). It answers with a
:class:`UrdfPlatform`: the model, its reference point on the ground and which joints are its wheels. It
writes itself as the :class:`UrdfJoint` list of :meth:`~mobman.model.platforms.base.Platform.urdf_joints`. So
a new wheeled platform is one module: the vocabulary of wheels, axles and steering joints is shared.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, NamedTuple, Protocol, TypeVar

if TYPE_CHECKING:
    from mobman.model.platforms.base import Platform

P = TypeVar("P", bound="Platform")


class UrdfWheel(NamedTuple):
    """A wheel joint of a URDF file: its name and the centre of its link in the base link's frame (m)."""

    name: str
    x: float
    y: float
    z: float


def midpoint(a: UrdfWheel, b: UrdfWheel) -> tuple[float, float]:
    """(x, y) of the middle of two wheels (an axle's midpoint)."""
    return ((a.x + b.x) / 2, (a.y + b.y) / 2)


def distance(a: UrdfWheel, b: UrdfWheel) -> float:
    """The distance between two wheel centres (m)."""
    return math.dist((a.x, a.y, a.z), (b.x, b.y, b.z))


class UrdfPlatform(NamedTuple):
    """A platform read from a URDF: the model, its reference point (x, y) in the base link (the platform
    frame), its wheel joints in the order of :meth:`Platform.wheels`, the (right, left) pair that the
    reading's summary names (None: no wheels) and ``base_height``, the base link's height above the ground
    the wheels define (:meth:`UrdfReader.base_height`), where the platform frame is; None: no wheel defines
    it, the platform frame is at the base link's height."""

    platform: Platform
    reference: tuple[float, float] = (0.0, 0.0)
    wheel_joints: tuple[str, ...] = ()
    sides: tuple[str, str] | None = None
    base_height: float | None = None


class UrdfReader(Protocol):
    """The view of a URDF file a platform reads itself from (implemented by :mod:`mobman.io.urdf`).

    Wheel joints are the continuous joints off the arm chains hanging from the platform; an axle is a pair of
    them on a common horizontal axis along the base link's y axis (ModelError naming the joints otherwise).
    """

    def wheel_pair(self) -> tuple[UrdfWheel, UrdfWheel]:
        """The one axle of the file as (right, left), or the pair named with ``wheels=``; ModelError listing
        the continuous joints when there is none, or naming the pairs when several qualify."""
        ...

    def axles(self) -> list[tuple[UrdfWheel, UrdfWheel]]:
        """Every axle of the file as (right, left)."""
        ...

    def continuous_joints(self) -> tuple[str, ...]:
        """The names of the wheel-joint candidates seen (for error messages)."""
        ...

    def steering_joints(self) -> list[UrdfWheel]:
        """The revolute joints about the vertical, off the chains, on the platform (their links' centres)."""
        ...

    def wheel_radius(self, wheel: UrdfWheel) -> float:
        """The radius of a wheel from its link's geometry, or the ``wheel_radius=`` given."""
        ...

    def half_track(self, measured: float) -> float:
        """``measured``, or the ``half_track=`` given."""
        ...

    def base_height(self, wheels: Sequence[UrdfWheel], radius: float | None = None) -> float | None:
        """The base link's height above the ground the ``wheels`` stand on: the wheel radius (``radius``, else
        the one given, else the first wheel's geometry; None when nothing gives it) less the wheel centres'
        mean height in the base link; 0 within 1 µm (a radius measured on a mesh carries its single-precision
        rounding)."""
        ...

    def without_wheels(self, *names: str) -> bool:
        """Whether the file has no axle (none found, none named with ``wheels=``) and the caller gave every
        one of the platform parameters ``names`` (``wheel_radius=``, ``half_track=``, ``platform_options``):
        then the platform is built from them alone, its frame at the base link (wheels that are fixed joints
        or absent, as in simulator exports)."""
        ...

    def wheel_speed(self, wheels: Sequence[UrdfWheel]) -> float | None:
        """The smallest velocity limit of the wheel joints (rad/s), None unless every one gives one."""
        ...

    def build(self, cls: type[P], **values: Any) -> P:
        """``cls(**values)`` with the ``platform_options`` added (ModelError naming a key that is not one of
        ``cls``'s parameters); values that are not parameters of ``cls`` are dropped."""
        ...


class UrdfJoint(NamedTuple):
    """A joint of a platform's URDF form, attached to ``parent`` (``"base_footprint"`` or the link of another
    joint, ``<name>_link``) at ``xyz``. A wheel (``radius`` set) is a continuous joint turning about the
    parent's y axis with a cylinder link, ``speed`` its velocity limit (rad/s) and ``driven`` whether it
    carries the dynamic model's wheel inertia; a steering joint (``radius`` None) is revolute about the
    vertical between ``limits``."""

    name: str
    parent: str
    xyz: tuple[float, float, float]
    radius: float | None = None
    speed: float | None = None
    driven: bool = False
    limits: tuple[float, float] | None = None


__all__ = ["UrdfJoint", "UrdfPlatform", "UrdfReader", "UrdfWheel", "distance", "midpoint"]
