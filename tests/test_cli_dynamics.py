"""`mobman load-capacity` (mobman.cli.dynamics): its spec file's errors name the field, on one line, exit 2."""

from __future__ import annotations

from pathlib import Path

import pytest

from mobman.cli import main

EXAMPLE = Path(__file__).resolve().parents[1] / "docs" / "examples" / "korayem_load.toml"


def _spec(tmp_path: Path, old: str, new: str) -> str:
    text = EXAMPLE.read_text()
    assert old in text
    path = tmp_path / "spec.toml"
    path.write_text(text.replace(old, new, 1))
    return str(path)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("mass = 40.0", "mass = -40.0", "platform: PlatformBody: mass must be a finite number > 0"),
        ("I_w = 0.005", "I_w = -0.005", "wheel: Wheel: I_w must be a finite number ≥ 0"),
        (
            "inertia = [0.0, 0.10416666666666667, 0.10416666666666667]",
            "inertia = [0.0, -1.0, 0.1]",
            "links[0]: LinkInertial: inertia must be positive semi-definite",
        ),
        ("mass = 5.0", "mass = 0.0", "links[0]: LinkInertial: mass must be"),
        (
            "stall_torque = 63.22 ",
            "stall_torque = -63.22 ",
            "actuators.theta1: DCMotor: stall_torque must be",
        ),
        ("no_load_speed = 3.5 ", "no_load_speed = 0 ", "actuators.theta1: DCMotor: no_load_speed must be"),
        ("[actuators.theta1]", "[actuators.shoulder]", "actuators.shoulder: unknown actuator"),
        ('kind = "dc_motor"', 'kind = "hydraulic"', "actuators.theta1.kind: 'hydraulic' not one of"),
        ("case = 1 ", "case = 3 ", "motion.case: 1"),
        ("[payload]", "[payload]\narm = 4", "payload.arm: an arm index in 0..0"),
    ],
)
def test_cli_errors_name_the_field(tmp_path, capsys, old, new, message):
    with pytest.raises(SystemExit) as exc:
        main(["load-capacity", _spec(tmp_path, old, new), "--json"])
    assert exc.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and message in err


def test_cli_missing_link_and_file(tmp_path, capsys):
    text = EXAMPLE.read_text()
    cut = text.index("[[links]]                                        # theta2")
    path = tmp_path / "one_link.toml"
    path.write_text(text[:cut] + text[text.index("[payload]") :])
    with pytest.raises(SystemExit) as exc:
        main(["load-capacity", str(path)])
    assert exc.value.code == 2
    assert "links: arm 0 has 2 links" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["load-capacity", str(tmp_path / "missing.toml")])
    assert "cannot read" in capsys.readouterr().err
