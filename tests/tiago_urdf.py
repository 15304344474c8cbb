"""TIAGo's joint limits read from its URDF file itself (ElementTree, not mobman's reader), the reference
values of the real-robot control tests, and its tool positions by Pinocchio on the same file."""

import xml.etree.ElementTree as ET

import numpy as np

from mobman.io.real_robots import REAL_ROBOTS


def joint_limits(names, keys=("lower", "upper")):
    """The ``keys`` attributes of each named joint's <limit> element, shape (len(names), len(keys))."""
    joints = {j.get("name"): j for j in ET.parse(REAL_ROBOTS["tiago"].path()).getroot().findall("joint")}
    return np.array([[float(joints[n].find("limit").get(k)) for k in keys] for n in names])


def pinocchio_tool_positions(robot, q: np.ndarray) -> np.ndarray:
    """Positions (n, 3) of TIAGo's ``arm_tool_link`` at mobman's configurations ``q`` (n, n_q) by Pinocchio's
    forward kinematics on the URDF file (planar root joint, the joints off mobman's chain locked at 0)."""
    import pinocchio as pin

    full = pin.buildModelFromUrdf(str(REAL_ROBOTS["tiago"].path()), pin.JointModelPlanar())
    keep = {j.name for arm in robot.arms for j in arm.joints}
    locked = [i for i in range(2, full.njoints) if full.names[i] not in keep]
    model = pin.buildReducedModel(full, locked, pin.neutral(full))
    data = model.createData()
    frame = model.getFrameId("arm_tool_link")
    out = []
    for qi in q:
        q_pin = np.zeros(model.nq)
        q_pin[:4] = qi[0], qi[1], np.cos(qi[2]), np.sin(qi[2])
        for k, joint in enumerate(j for arm in robot.arms for j in arm.joints):
            q_pin[model.idx_qs[model.getJointId(joint.name)]] = qi[3 + k]
        pin.framesForwardKinematics(model, data, q_pin)
        out.append(data.oMf[frame].translation.copy())
    return np.array(out)
