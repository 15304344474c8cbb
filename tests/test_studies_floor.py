"""Keep-out regions and the platform's footprint (mobman.studies.floor), and base placement that keeps the
platform off the regions (mobman.studies.placement): the overlap test in closed form at headings 0, ±π/2 and
π and against a dense sampling of the disc, the covering disc of drawn shapes in closed form and of TIAGo's
meshes against PAL's base diameter, and the errors."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from mobman import kinematics as K
from mobman.errors import InputError
from mobman.model import robots, spatial
from mobman.model.tasks import Position
from mobman.model.visual import Visual
from mobman.studies.floor import (
    ROUND_POINTS,
    FootprintDisc,
    KeepOut,
    blocked,
    footprint_disc,
    keep_out_regions,
)
from mobman.studies.placement import place, place_with_map

TABLE = KeepOut(1.0, 2.0, -1.0, 1.0)
COVER = 1.0 / math.cos(math.pi / ROUND_POINTS)
"""How much wider than a round shape its covering polygon's circle is."""


@pytest.mark.parametrize(
    ("base", "expected"),
    [
        ((0.69, 0.0, 0.3), False),  # 0.31 m from the table's near side
        ((0.71, 0.0, -2.0), True),  # 0.29 m
        ((1.5, 0.0, 1.0), True),  # on the table
        ((0.8, 1.2, 0.0), True),  # the corner 0.2 √2 = 0.283 m away
        ((0.78, 1.22, 0.0), False),  # 0.22 √2 = 0.311 m
        ((2.29, -1.0, 0.0), True),  # the far side, 0.29 m
    ],
)
def test_a_disc_about_the_platform_s_origin_overlaps_within_its_radius_of_the_rectangle(base, expected):
    assert blocked([base], FootprintDisc(0.3), [TABLE])[0] == expected


def test_a_disc_that_touches_a_side_does_not_overlap_it():
    assert not blocked([(0.75, 0.0, 0.0)], FootprintDisc(0.25), [TABLE])[0]  # 1 − 0.75 = 0.25 exactly
    assert blocked([(0.75, 0.0, 0.0)], FootprintDisc(0.25 + 1e-12), [TABLE])[0]


@pytest.mark.parametrize(
    ("theta", "expected"),
    [
        (0.0, True),  # the disc ahead of the platform, at x = 0.95: on the table's near side
        (math.pi, False),  # behind it, at x = −0.05
        (-math.pi, False),
        (math.pi / 2, False),  # to its left, at (0.45, 0.5)
        (-math.pi / 2, False),
    ],
)
def test_a_disc_off_the_platform_s_origin_turns_with_the_platform(theta, expected):
    disc = FootprintDisc(0.1, x=0.5)
    assert blocked([(0.45, 0.0, theta)], disc, [TABLE])[0] == expected
    # a disc to the platform's left is ahead of it once it turns by −π/2, behind it by π/2
    left = FootprintDisc(0.1, y=0.5)
    assert blocked([(0.45, 0.0, theta - math.pi / 2)], left, [TABLE])[0] == expected


def test_the_overlap_agrees_with_a_dense_sampling_of_the_disc():
    rng = np.random.default_rng(3)
    bases = np.c_[rng.uniform(-1.0, 3.0, (800, 2)), rng.uniform(-np.pi, np.pi, 800)]
    bases[:4, 2] = [np.pi / 2, -np.pi / 2, np.pi, -np.pi]
    disc = FootprintDisc(0.35, x=-0.1, y=0.05)
    regions = [TABLE, KeepOut(-0.5, 0.2, 1.5, 1.7)]
    # the disc's points: 200 rings of 400 points, from the centre to the radius (inclusive of the boundary)
    radius, angle = np.meshgrid(
        np.linspace(0, disc.radius, 200), np.linspace(0, 2 * np.pi, 400, endpoint=False)
    )
    local = np.c_[disc.x + (radius * np.cos(angle)).ravel(), disc.y + (radius * np.sin(angle)).ravel()]
    c, s = np.cos(bases[:, 2])[:, None], np.sin(bases[:, 2])[:, None]
    x = bases[:, :1] + c * local[:, 0] - s * local[:, 1]
    y = bases[:, 1:2] + s * local[:, 0] + c * local[:, 1]
    inside = np.zeros(len(bases), dtype=bool)
    near_an_edge = np.zeros(len(bases), dtype=bool)  # a side within 5 mm of the disc's rim: left out
    for r in regions:
        inside |= np.any((x > r.x_min) & (x < r.x_max) & (y > r.y_min) & (y < r.y_max), axis=1)
        grown = [(r.x_min - d, r.x_max + d, r.y_min - d, r.y_max + d) for d in (-5e-3, 5e-3)]
        near_an_edge |= np.any(
            (x > grown[1][0]) & (x < grown[1][1]) & (y > grown[1][2]) & (y < grown[1][3]), axis=1
        ) != np.any((x > grown[0][0]) & (x < grown[0][1]) & (y > grown[0][2]) & (y < grown[0][3]), axis=1)
    clear_of_the_edge = ~near_an_edge
    got = blocked(bases, disc, regions)
    np.testing.assert_array_equal(got[clear_of_the_edge], inside[clear_of_the_edge])
    assert 0.2 < got.mean() < 0.8


def test_no_region_blocks_nothing():
    np.testing.assert_array_equal(blocked(np.zeros((3, 3)), FootprintDisc(1.0), []), False)


def test_the_disc_of_drawn_shapes_covers_them_in_closed_form():
    def disc_of(*visuals):
        return footprint_disc(replace(robots.bayle_planar(), platform_visuals=visuals))

    turned = spatial.transform(spatial.rot_z(math.pi / 2), (0.3, -0.2, 0.1))
    box = disc_of(Visual("box", origin=turned, size=(0.4, 0.2, 0.5)))  # 0.2 along x, 0.4 along y once turned
    assert (box.x, box.y) == pytest.approx((0.3, -0.2)) and box.radius == pytest.approx(math.hypot(0.2, 0.1))
    upright = disc_of(Visual("cylinder", size=(0.3, 0.1)))
    assert (upright.x, upright.y) == pytest.approx((0, 0), abs=1e-15)
    assert upright.radius == pytest.approx(0.3 * COVER)
    lying = disc_of(Visual("cylinder", origin=spatial.transform(spatial.rot_x(math.pi / 2)), size=(0.1, 0.6)))
    assert lying.radius == pytest.approx(math.hypot(0.1 * COVER, 0.3))  # a 0.2 × 0.6 rectangle from above
    sphere = disc_of(Visual("sphere", origin=spatial.transform(None, (0.1, 0.0, 0.5)), size=(0.2,)))
    assert (sphere.x, sphere.radius) == pytest.approx((0.1, 0.2 * COVER))
    both = disc_of(
        Visual("sphere", size=(0.1,)),
        Visual("sphere", origin=spatial.transform(None, (1, 0, 0)), size=(0.1,)),
    )
    assert (both.x, both.y, both.radius) == pytest.approx((0.5, 0.0, 0.5 + 0.1 * COVER))


def test_a_robot_without_drawn_shapes_is_covered_by_its_platform_s_body_box():
    robot = robots.build("tchon-car-rtr")
    box = robot.platform.footprint()
    disc = footprint_disc(robot)
    assert (disc.x, disc.y) == pytest.approx((box.x_centre, 0.0))
    assert disc.radius == pytest.approx(math.hypot(box.length, box.width) / 2)


def test_tiago_s_disc_covers_its_base_meshes_and_matches_pal_s_base_diameter():
    """PAL gives the PMB2 base's diameter as 54 cm; the disc is centred on the base within 5 mm."""
    disc = footprint_disc(robots.build("tiago"))
    assert disc.radius == pytest.approx(0.27, abs=0.005)
    assert math.hypot(disc.x, disc.y) <= 0.005


def test_the_errors_name_the_field_and_its_range():
    with pytest.raises(
        InputError, match=r"^keep_out must have x_min < x_max and y_min < y_max .*got 1, 1, 0, 1$"
    ):
        KeepOut(1.0, 1.0, 0.0, 1.0)
    with pytest.raises(InputError, match=r"^keep_out must be 4 finite numbers"):
        KeepOut(0.0, math.inf, 0.0, 1.0)
    with pytest.raises(InputError, match=r"^keep_out must be 4 numbers .*shape \(3,\)"):
        keep_out_regions([[0, 1, 2]])
    with pytest.raises(InputError, match=r"^footprint radius must be > 0 \(m\), got 0$"):
        FootprintDisc.of(0.0)
    for bad in ([0.3, 0.1], "wide"):
        with pytest.raises(InputError, match=r"^footprint must be a radius, or radius, x, y"):
            FootprintDisc.of(bad)  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"^footprint must be finite numbers"):
        FootprintDisc.of(np.nan)


def test_regions_are_given_one_or_many():
    assert keep_out_regions((1, 2, -1, 1)) == (TABLE,)
    assert keep_out_regions([TABLE, (0, 1, 0, 1)]) == (TABLE, KeepOut(0, 1, 0, 1))
    assert keep_out_regions(np.array([[1, 2, -1, 1]])) == (TABLE,)
    assert keep_out_regions([]) == ()


L1 = L2 = 0.5


def test_placement_keeps_the_platform_off_the_regions_and_finds_the_best_elsewhere():
    """Bayle's 2R arm: the best bases are √(l1² + l2²) from the target on every bearing (w = l1 l2); a wall
    south of the target blocks the bases near it, and the best is found on another bearing."""
    robot = robots.build("bayle-planar", l1=L1, l2=L2).with_task(Position("xy"))
    target = np.array([0.3, -0.4])
    grid = dict(radii=[0.2, 0.5, math.hypot(L1, L2), 0.9], bearings=4, headings=4, starts=4)
    wall = (-3.0, 3.0, -3.0, -0.5)
    free = place(robot, target, **grid)
    result = place(robot, target, keep_out=[wall], footprint=0.2, **grid)
    assert not free.blocked.any() and free.footprint is None
    assert result.footprint == FootprintDisc(0.2)
    # a base is blocked when its disc reaches below y = −0.5, i.e. when y < −0.3
    np.testing.assert_array_equal(result.blocked, result.bases[:, 1] - 0.2 < -0.5)
    np.testing.assert_array_equal(result.reached, free.reached & ~result.blocked)
    np.testing.assert_array_equal(result.score[result.blocked], 0.0)
    best = result.bases[result.best]
    assert best[1] >= -0.3 and result.score[result.best] == pytest.approx(L1 * L2, abs=1e-9)
    assert np.abs(np.asarray(K.forward(robot, result.q[result.best])) - target).max() <= 1e-9
    everywhere = place(robot, target, keep_out=(-9, 9, -9, 9), footprint=0.1, **grid)
    assert everywhere.blocked.all() and not everywhere.reached.any() and everywhere.best is None


def test_placement_from_a_map_keeps_the_platform_off_the_regions():
    from mobman.studies.maps import reachability_map

    robot = robots.bayle_planar(l1=0.7, l2=0.4)
    reachability = reachability_map(robot, bounds=[-1.2, 1.2, -1.2, 1.2, 0, 0], step=0.2, starts=4)
    target = np.array([0.3, -0.4, 0.0])
    disc = footprint_disc(robot)
    result = place_with_map(robot, reachability, target, headings=4, keep_out=[(0.3, 3.0, -3.0, 3.0)])
    assert result.footprint == disc
    np.testing.assert_array_equal(result.blocked, result.bases[:, 0] + disc.radius > 0.3)
    assert result.reached.any() and not (result.reached & result.blocked).any()
    assert result.bases[result.best][0] <= 0.3 - disc.radius
