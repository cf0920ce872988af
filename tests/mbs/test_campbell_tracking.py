"""Campbell branches followed by mode shape (MAC) through a crossing: a Jeffcott rotor whose forward
tilt branch (gyroscopic splitting, closed form) crosses a torsional mode of constant frequency."""

from __future__ import annotations

import numpy as np

from ddgsa.mbs import Bushing6, Ground, RigidBody, System
from ddgsa.mbs.campbell import campbell, mac, track
from test_campbell import closed_form, jeffcott

J_WHEEL = 1.0                                      # polar inertia of the torsional oscillator [kg m^2]
SPEEDS = np.linspace(0.0, 500.0, 11)               # [rad/s]


def with_torsional_mode(f_torsion: float) -> System:
    """The Jeffcott rotor of ``test_campbell`` beside a wheel on a torsion spring of ``f_torsion`` [Hz]
    (its other directions clamped far above the band): uncoupled, so the branches cross exactly."""
    rotor = jeffcott()
    wheel = RigidBody("wheel", 1.0, (J_WHEEL, 1.0, 1.0), position=(5.0, 0.0, 0.0))
    k = np.diag([1e12, 1e12, 1e12, J_WHEEL * (2 * np.pi * f_torsion) ** 2, 1e12, 1e12])
    mount = Bushing6(wheel.marker(), Ground().marker((5.0, 0.0, 0.0)), k, name="wheel_mount")
    return System(rotor.bodies + [wheel], rotor.elements + [mount])


def test_mac_of_shapes() -> None:
    a = np.array([[1.0, 0.0], [1j, 1.0]])
    m = mac(a, a * (2 - 1j))
    np.testing.assert_allclose(np.diag(m), 1.0, rtol=1e-12)              # scaling by a complex number: same shape
    np.testing.assert_allclose(m[0, 1], 0.5, rtol=1e-12)                 # (1, j) against (0, 1): |j|^2 / (2 * 1)


def test_track_follows_swapped_columns() -> None:
    rng = np.random.default_rng(0)
    base = rng.standard_normal((6, 4)) + 1j * rng.standard_normal((6, 4))
    order = np.array([2, 0, 3, 1])
    branches = track([base, base[:, order] * 1.1])
    np.testing.assert_array_equal(branches[1], order)


def test_forward_branch_keeps_its_name_through_a_torsional_crossing() -> None:
    f_fwd = [closed_form(w)[2] for w in SPEEDS]
    f_torsion = 0.5 * (f_fwd[0] + f_fwd[-1])                            # crossed between the end speeds
    diagram = campbell(with_torsional_mode(f_torsion), SPEEDS, spin="disc.rx")
    fr = diagram.to_frame()
    # ranked by frequency, the forward tilt mode's rank changes across the crossing
    ranks = [int(np.argmin(np.abs(np.sort(g["frequency_hz"].to_numpy()) - f)))
             for (_, g), f in zip(fr.groupby("speed_rad_s"), f_fwd)]
    assert ranks[0] != ranks[-1]
    # tracked, one branch is the closed-form forward tilt frequency at every speed, one the torsion
    fwd_branch = fr.loc[(fr["speed_rad_s"] == SPEEDS[-1])].iloc[
        np.argmin(np.abs(fr.loc[fr["speed_rad_s"] == SPEEDS[-1], "frequency_hz"] - f_fwd[-1]))]["mode"]
    fwd = fr[fr["mode"] == fwd_branch].sort_values("speed_rad_s")
    np.testing.assert_allclose(fwd["frequency_hz"], f_fwd, rtol=1e-6)
    assert set(fwd.loc[fwd["speed_rad_s"] > 0, "whirl"]) == {"forward"}
    tors = fr[np.isclose(fr["frequency_hz"], f_torsion, rtol=1e-6)]
    assert tors["mode"].nunique() == 1 and len(tors) == SPEEDS.size       # one branch, every speed
    # crossings of the 1x line by the backward tilt branch, not a rank jump, would show here: none below 500 rad/s
    assert diagram.crossings(1.0)["mode"].nunique() == 2                  # the lateral pair only
