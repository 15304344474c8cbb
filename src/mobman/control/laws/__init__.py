"""Operational control laws with redundancy resolution, η = law(q, t, ξ*, ξ̇*), one module per law;
:mod:`mobman.control.laws.base` has the :class:`Law` interface, the typed result :class:`LawStep` and the
registry.

:class:`BaylePseudoInverse` — Bayle eq. (5)–(6), :class:`NaitChabane` — Nait-Chabane eq. (30),
:class:`AugmentedJacobian` — Korayem eq. (30), :class:`WholeBodyQP` — Bayle's law as a quadratic program
within the velocity, wheel-speed and joint limits. Every module of this package is imported here, so a new file
with a :class:`Law` subclass that sets ``kind`` is found by :func:`law_class` (specification files name laws
by kind) without any other edit.
"""

from mobman.control.laws.augmented import AugmentedJacobian, AugmentedStep
from mobman.control.laws.base import Law, LawStep, apply_gain, damped_inverse, law_class, law_kinds
from mobman.control.laws.bayle import BaylePseudoInverse
from mobman.control.laws.nait_chabane import NaitChabane
from mobman.control.laws.pseudo_inverse import PseudoInverseLaw, PseudoInverseStep
from mobman.control.laws.qp import QPStep, WholeBodyQP
from mobman.model.kinds import import_package

import_package(__name__, __path__)

__all__ = [
    "AugmentedJacobian",
    "AugmentedStep",
    "BaylePseudoInverse",
    "Law",
    "LawStep",
    "NaitChabane",
    "PseudoInverseLaw",
    "PseudoInverseStep",
    "QPStep",
    "WholeBodyQP",
    "apply_gain",
    "damped_inverse",
    "law_class",
    "law_kinds",
]
