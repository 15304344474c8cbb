"""The platforms, one module each, found by ``kind`` (:func:`platform_class`).

Importing this package imports every module in it, so a new platform module registers itself.
"""

from mobman.model.kinds import import_package
from mobman.model.platforms.base import Footprint, Platform, WheelSite, platform_class, platform_kinds
from mobman.model.platforms.car import CarLike
from mobman.model.platforms.differential import DifferentialDrive
from mobman.model.platforms.fixed import Fixed
from mobman.model.platforms.omnidirectional import Omnidirectional
from mobman.model.platforms.skid_steer import SkidSteer

import_package(__name__, __path__)

__all__ = [
    "CarLike",
    "DifferentialDrive",
    "Fixed",
    "Footprint",
    "Omnidirectional",
    "Platform",
    "SkidSteer",
    "WheelSite",
    "platform_class",
    "platform_kinds",
]
