"""TIAGo's joint limits read from its URDF file itself (ElementTree, not mobman's reader): the reference
values of the real-robot control tests."""

import xml.etree.ElementTree as ET

import numpy as np

from mobman.io.real_robots import REAL_ROBOTS


def joint_limits(names, keys=("lower", "upper")):
    """The ``keys`` attributes of each named joint's <limit> element, shape (len(names), len(keys))."""
    joints = {j.get("name"): j for j in ET.parse(REAL_ROBOTS["tiago"].path()).getroot().findall("joint")}
    return np.array([[float(joints[n].find("limit").get(k)) for k in keys] for n in names])
