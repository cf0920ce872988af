"""Campbell diagram of a Jeffcott rotor: closed-form gyroscopic splitting and ROSS as oracles."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.mbs import Bushing6, Ground, RigidBody, System
from ddgsa.mbs.campbell import campbell

E, G_SHEAR = 211e9, 81.2e9
LENGTH, DIAMETER = 1.0, 0.05                      # shaft between the bearings [m]
MASS, J_DIAM, J_POLAR = 20.0, 0.3, 0.5            # disc at mid-span [kg, kg m^2]
K_BEARING = 1e9                                   # each bearing [N/m]
SPEEDS = np.array([0.0, 200.0, 500.0])            # [rad/s]


def midspan_stiffness() -> tuple[float, float]:
    """Lateral and tilt stiffness at mid-span of a pinned-pinned massless shaft on elastic bearings."""
    ei = E * np.pi * DIAMETER ** 4 / 64
    lateral = 1.0 / (LENGTH ** 3 / (48 * ei) + 1.0 / (2 * K_BEARING))
    tilt = 1.0 / (LENGTH / (12 * ei) + 2.0 / (LENGTH ** 2 * K_BEARING))
    return lateral, tilt


def jeffcott() -> System:
    lateral, tilt = midspan_stiffness()
    ea = E * np.pi * DIAMETER ** 2 / 4
    disc = RigidBody("disc", MASS, (J_POLAR, J_DIAM, J_DIAM))
    shaft = Bushing6(disc.marker(), Ground().marker(), np.diag([4 * ea / LENGTH, lateral, lateral, 0.0, tilt, tilt]),
                     free_spin=True, name="shaft")
    return System([disc], [shaft])


def closed_form(speed: float) -> tuple[float, float, float]:
    """Lateral, backward and forward tilt frequencies [Hz]: J_d w^2 -+ J_p W w - k_t = 0."""
    lateral, tilt = midspan_stiffness()
    root = np.sqrt((J_POLAR * speed) ** 2 + 4 * J_DIAM * tilt)
    return (np.sqrt(lateral / MASS) / (2 * np.pi), (root - J_POLAR * speed) / (2 * J_DIAM) / (2 * np.pi),
            (root + J_POLAR * speed) / (2 * J_DIAM) / (2 * np.pi))


def test_jeffcott_gyroscopic_splitting_closed_form() -> None:
    diagram = campbell(jeffcott(), SPEEDS, spin="disc.rx", orders=(1,))
    fr = diagram.to_frame()
    for speed in SPEEDS[1:]:
        rows = fr[fr["speed_rad_s"] == speed].set_index("mode")
        lateral, backward, forward = closed_form(speed)
        np.testing.assert_allclose(rows.loc[[1, 2], "frequency_hz"], lateral, rtol=1e-6)
        # the translational pair is degenerate (no gyroscopic coupling): any orbit, no whirl to assert
        tilt = rows[rows["label"].str.contains("tilt")]
        np.testing.assert_allclose(tilt["frequency_hz"], [backward, forward], rtol=1e-6)
        assert list(tilt["whirl"]) == ["backward", "forward"]
    # 1P crossings below 500 rad/s: the lateral pair at its critical speed sqrt(k/m); the forward tilt
    # mode never meets 1P for a disc (J_p > J_d) and the backward one only at sqrt(k_t/(J_d + J_p)) = 985 rad/s
    crossings = diagram.crossings(1.0)
    assert sorted(crossings["mode"]) == [1, 2]
    np.testing.assert_allclose(crossings["speed_rad_s"], np.sqrt(midspan_stiffness()[0] / MASS), rtol=1e-6)


@pytest.mark.slow        # ROSS imports in ~20 s; the closed-form Jeffcott test above is the fast check of the same rotor
def test_jeffcott_against_ross() -> None:
    """Same rotor in ROSS (Euler-Bernoulli shaft elements of 1e-5 steel density, 0.15 g): frequencies within 1e-5."""
    rs = pytest.importorskip("ross", reason="ROSS is the optional oracle: pip install -e '.[oracles]'")
    material = rs.Material(name="light_steel", rho=0.0781, E=E, G_s=G_SHEAR)
    shaft = [rs.ShaftElement(L=LENGTH / 2, idl=0.0, odl=DIAMETER, material=material, shear_effects=False,
                             rotary_inertia=False, gyroscopic=False) for _ in range(2)]
    rotor = rs.Rotor(shaft, [rs.DiskElement(n=1, m=MASS, Id=J_DIAM, Ip=J_POLAR)],
                     [rs.BearingElement(n=n, kxx=K_BEARING, kyy=K_BEARING, cxx=0.0, cyy=0.0) for n in (0, 2)])
    fr = campbell(jeffcott(), SPEEDS, spin="disc.rx").to_frame()
    for speed in SPEEDS:
        ours = np.sort(fr.loc[fr["speed_rad_s"] == speed, "frequency_hz"].to_numpy())[:4]
        theirs = np.sort(rotor.run_modal(speed=speed, num_modes=12).wn / (2 * np.pi))[:4]
        np.testing.assert_allclose(ours, theirs, rtol=1e-5)


def test_campbell_plot_and_table(tmp_path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    diagram = campbell(jeffcott(), np.linspace(0, 400, 5), spin="disc.rx", orders=(1, 2))
    fr = diagram.to_frame()
    ax = diagram.plot(max_frequency_hz=1.1 * fr["frequency_hz"].max())      # every mode (by default: the orders' range)
    assert fr["mode"].nunique() == 5                               # lateral pair, tilt pair, axial
    assert len(ax.lines) == 5 + 2                                  # one line per mode, two order lines
    assert set(fr.columns) >= {"speed_rpm", "mode", "frequency_hz", "whirl", "label"}
    assert set(fr.loc[fr["label"] == "disc_axial", "whirl"]) == {"none"}
